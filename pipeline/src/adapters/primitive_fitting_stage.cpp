#include "adapters.h"

#include "slipfit/pipeline/errors.h"
#include "slipfit/pipeline/output_files.h"
#include "slipfit/pipeline/primitives_report.h"
#include "slipfit/weighted_fit.h"

#include <cmath>
#include <fstream>
#include <map>
#include <ostream>

namespace slipfit::pipeline::adapters {

namespace {

enum class FitType { automatic, plane, sphere, cylinder, cone };
constexpr std::array<std::pair<FitType, std::string_view>, 5> kFitTypeNames{{
    {FitType::automatic, "auto"},
    {FitType::plane, "plane"},
    {FitType::sphere, "sphere"},
    {FitType::cylinder, "cylinder"},
    {FitType::cone, "cone"},
}};

class PrimitiveFittingStage : public Stage {
 public:
  void declare(OptionSet& o) override {
    o.add("primitive", type_, kFitTypeNames,
          "Primitive to fit; auto fits all four and keeps the least BIC (more parameters must "
          "explain the data clearly better).");
    o.add("labels", labels_,
          "Integer per-point field: fit one primitive per label >= 0 (unset: the whole cloud).");
    o.add("weights", weights_, "Per-point field of non-negative weights (unset: all 1).");
    o.add("refine", options_.refine,
          "Refine the closed-form estimate on the true geometric distance (Levenberg–Marquardt).");
    o.add("max_iterations", options_.max_iterations, "Refinement iterations at most.")
        .range(1, 10000);
    o.add("inlier_distance", inlier_distance_,
          "Points within this distance count as inliers (unset: 3 × each fit's RMS distance).")
        .unit("units")
        .above(0);
    o.add("min_points", min_points_, "Labels with fewer points are reported, not fitted.")
        .unit("points")
        .range(3, 1e9);
    o.add("report", report_, "File name of the YAML report in the output dir.");
  }

  DataFlow flow() const override {
    const bool normals = type_ == FitType::cylinder || type_ == FitType::cone;
    return {normals ? (kPoints | kNormals) : kPoints, 0u};
  }

  void run(PointData& data, RunContext& context) override {
    const std::size_t n = data.size();
    std::vector<double> weights(n, 1.0);
    if (!weights_.empty()) {
      weights = data.numericField(weights_);
      if (weights.size() != n)
        throw RunError("no per-point field '" + weights_ + "' for the weights");
      for (std::size_t i = 0; i < n; ++i)
        if (!(weights[i] >= 0.0) || !std::isfinite(weights[i]))
          throw RunError("weight field '" + weights_ + "': point " + std::to_string(i) + " has " +
                         std::to_string(weights[i]) + " (weights must be finite and >= 0)");
    }
    std::map<int, std::vector<std::size_t>> groups;
    if (labels_.empty()) {
      auto& all = groups[-1];
      all.resize(n);
      for (std::size_t i = 0; i < n; ++i)
        all[i] = i;
    } else {
      const std::vector<double> labels = data.numericField(labels_);
      if (labels.size() != n)
        throw RunError("no per-point field '" + labels_ + "' for the labels");
      for (std::size_t i = 0; i < n; ++i)
        if (labels[i] >= 0.0 && std::isfinite(labels[i]))
          groups[static_cast<int>(labels[i])].push_back(i);
    }

    std::vector<PrimitiveRecord> records;
    std::vector<float> fit_distance(n, -1.0f);
    for (const auto& [label, members] : groups) {
      PrimitiveRecord record;
      record.id = static_cast<int>(records.size());
      if (label >= 0)
        record.label = label;
      const auto m = static_cast<Eigen::Index>(members.size());
      Eigen::Matrix3Xd points(3, m), normals(3, data.has_normals ? m : 0);
      Eigen::VectorXd w(m);
      for (Eigen::Index j = 0; j < m; ++j) {
        const auto& p = (*data.cloud)[members[static_cast<std::size_t>(j)]];
        points.col(j) = p.getVector3fMap().cast<double>();
        if (data.has_normals)
          normals.col(j) = p.getNormalVector3fMap().cast<double>();
        w[j] = weights[members[static_cast<std::size_t>(j)]];
      }
      if (static_cast<int>(members.size()) < min_points_) {
        record.fit.status = FitStatus::too_few_points;
        record.fit.reason = std::to_string(members.size()) + " points, min_points is " +
                            std::to_string(min_points_);
      } else if (type_ == FitType::automatic) {
        record.fit = fitAuto(points, normals, w, options_);
      } else {
        record.fit = fitPrimitive(static_cast<PrimitiveType>(static_cast<int>(type_) - 1), points,
                                  normals, w, options_);
      }
      if (!record.fit.ok() && label < 0)
        throw RunError(record.fit.reason);
      if (record.fit.ok()) {
        record.inlier_distance = inlier_distance_.value_or(3.0 * record.fit.rms_distance);
        for (Eigen::Index j = 0; j < m; ++j) {
          const double d = distance(points.col(j), record.fit.refined);
          fit_distance[members[static_cast<std::size_t>(j)]] = static_cast<float>(d);
          if (w[j] > 0.0 && d <= record.inlier_distance)
            ++record.inliers;
        }
      }
      records.push_back(std::move(record));
    }
    data.setField({"fit_distance", std::move(fit_distance)});

    std::size_t shown = 0;
    for (const auto& r : records) {
      if (++shown > 20) {
        context.report << "fit: ... " << records.size() - 20 << " more in " << report_ << "\n";
        break;
      }
      context.report << "fit " << r.id
                     << (r.label ? " (label " + std::to_string(*r.label) + ")" : "") << ": ";
      if (!r.fit.ok()) {
        context.report << fitStatusName(r.fit.status) << ": " << r.fit.reason << "\n";
        continue;
      }
      context.report << primitiveTypeName(r.fit.type) << ", rms " << r.fit.rms_distance << ", "
                     << r.inliers << "/" << r.fit.used_points << " inliers, loss "
                     << r.fit.loss_algebraic << " -> " << r.fit.loss_refined << "\n";
    }
    if (!context.outputs)
      throw RunError("no output directory for the report");
    const std::string text = primitivesYaml(records, data_source_);
    context.outputs->add(report_, [&](const std::string& path) {
      std::ofstream out(path, std::ios::binary);
      out << text;
      out.close();
      if (!out)
        throw RunError("cannot write '" + path + "'");
    });
  }

 private:
  FitType type_ = FitType::automatic;
  std::string labels_, weights_;
  FitOptions options_;
  std::optional<double> inlier_distance_;
  int min_points_ = 10;
  std::string report_ = "primitives.yaml";
  std::string data_source_ = "slipfit primitive_fitting";
};

}  // namespace

StageInfo primitiveFittingInfo() {
  return {
      "primitive_fitting",
      "weighted plane/sphere/cylinder/cone fit per label or for the whole cloud, refined on the "
      "geometric distance; writes primitives.yaml",
      [] { return std::unique_ptr<Stage>(new PrimitiveFittingStage); }};
}

}  // namespace slipfit::pipeline::adapters
