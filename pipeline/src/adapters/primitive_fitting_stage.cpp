#include "adapters.h"

#include "slipfit/cloud_maps.h"
#include "slipfit/pipeline/errors.h"
#include "slipfit/pipeline/output_files.h"
#include "slipfit/pipeline/primitives_report.h"
#include "slipfit/robust_fit.h"
#include "slipfit/surface_noise.h"
#include "slipfit/weighted_fit.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <ostream>
#include <sstream>
#include <utility>

namespace slipfit::pipeline::adapters {

namespace {

/// Below this share of the points a fit is reported as not describing the cloud.
constexpr double kFewInliers = 0.5;

class PrimitiveFittingStage : public Stage {
 public:
  void declare(OptionSet& o) override {
    o.add("primitive", type_, "auto", kPrimitiveTypeNames,
          "Primitive to fit; auto fits every type and keeps the simplest adequate one (RMS "
          "within 25 % of the best, flat limits recognised: docs/THEORY.md §4.4), as the "
          "segmentation and the whole-cloud classification do.");
    o.add("labels", labels_,
          "Integer per-point field: fit one primitive per label >= 0 (unset: the whole cloud).");
    o.add("weights", weights_, "Per-point field of non-negative weights (unset: all 1).");
    o.bind(options_);
    o.add("inlier_distance", inlier_distance_,
          "Points within this distance count as inliers (unset: a robust fit's own threshold, "
          "else 3 × the surface noise measured from each fit's points, surface_noise.h; never "
          "the fit's own RMS, which would call most points of any fit inliers).")
        .unit("units")
        .above(0);
    o.add("min_points", min_points_, "Labels with fewer points are reported, not fitted.")
        .unit("points")
        .range(3, 1e9);
    o.add("robust", robust_choice_, "auto", kRobustMethodNames,
          "auto: ransac for a whole-cloud fit (a scan holds more than one surface and outliers), "
          "none per label; none: plain weighted fit; irls: Tukey-biweight reweighting; ransac: "
          "best of seeded minimal-sample hypotheses, then irls. Robust with primitive auto: the "
          "type with the most inliers wins (within 1 %, the simpler one).");
    o.bind(robust_, {{"threshold", "robust_threshold"}});
    o.add("report", report_, "File name of the YAML report in the output dir.").fileName();
  }

  DataFlow flow() const override {
    const bool normals = type_ && (*type_ == PrimitiveType::cylinder ||
                                   *type_ == PrimitiveType::cone || *type_ == PrimitiveType::torus);
    return {normals ? (kPoints | kNormals) : kPoints, 0u};
  }

  std::vector<std::string> outputFiles() const override { return {report_}; }

  void prepare() override {
    robust_.method =
        robust_choice_.value_or(labels_.empty() ? RobustMethod::ransac : RobustMethod::none);
    options_.validate();
    robust_.validate();
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
      std::vector<char> inliers;
      record.id = static_cast<int>(records.size());
      if (label >= 0)
        record.label = label;
      const auto m = static_cast<Eigen::Index>(members.size());
      const pcl::PointCloud<pcl::PointNormal>& cloud = *data.cloud;
      const Eigen::Matrix3Xd points = coordinates(cloud)(Eigen::all, members).cast<double>();
      const Eigen::Matrix3Xd normals =
          data.has_normals
              ? Eigen::Matrix3Xd(slipfit::normals(cloud)(Eigen::all, members).cast<double>())
              : Eigen::Matrix3Xd(3, 0);
      Eigen::VectorXd w(m);
      for (Eigen::Index j = 0; j < m; ++j)
        w[j] = weights[members[static_cast<std::size_t>(j)]];
      if (static_cast<int>(members.size()) < min_points_) {
        record.fit.status = FitStatus::too_few_points;
        record.fit.reason = std::to_string(members.size()) + " points, min_points is " +
                            std::to_string(min_points_);
      } else if (robust_.method != RobustMethod::none) {
        record.fit = robustFit(points, normals, w, context.seed, &inliers, &record.inlier_distance);
      } else if (!type_) {
        record.fit = fitAuto(points, normals, w, options_);
      } else {
        record.fit = fitPrimitive(*type_, points, normals, w, options_);
      }
      if (!record.fit.ok() && label < 0)
        throw RunError(record.fit.reason);
      if (record.fit.ok()) {
        record.inlier_distance = inlierDistance(points, normals, record);
        int given = 0;
        for (Eigen::Index j = 0; j < m; ++j) {
          const double d = distance(points.col(j), record.fit.refined);
          fit_distance[members[static_cast<std::size_t>(j)]] = static_cast<float>(d);
          given += w[j] > 0.0 ? 1 : 0;
          if (w[j] > 0.0 && d <= record.inlier_distance)
            ++record.inliers;
        }
        record.extra["points"] = std::to_string(given);
        if (record.inliers < kFewInliers * given)
          record.extra["warning"] =
              "only " + percent(record.inliers, given) + " of the points are inliers: the " +
              (label < 0 ? std::string("cloud") : "label") + " is not one " +
              std::string(primitiveTypeName(record.fit.type)) +
              (robust_.method == RobustMethod::ransac ? ""
                                                      : " (robust: ransac finds the largest one)");
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
                     << r.inliers << "/" << r.extra.at("points") << " inliers within "
                     << r.inlier_distance << " (" << r.extra.at("inlier_tolerance") << "), loss "
                     << r.fit.loss_algebraic << " -> " << r.fit.loss_refined << "\n";
      const auto warning = r.extra.find("warning");
      if (warning != r.extra.end())
        context.report << "fit " << r.id << ": warning: " << warning->second << "\n";
    }
    if (!context.outputs)
      throw RunError("no output directory for the report");
    context.outputs->addText(report_, primitivesYaml(records, data_source_, data.frame.shift));
  }

 private:
  /// The configured inlier distance, else the robust fit's threshold, else 3 σ̂ of the points
  /// (the tolerance is written to the report with where it came from).
  double inlierDistance(const Eigen::Matrix3Xd& points, const Eigen::Matrix3Xd& normals,
                        PrimitiveRecord& record) const {
    if (inlier_distance_) {
      record.extra["inlier_tolerance"] = "set in the config";
      return *inlier_distance_;
    }
    if (robust_.method != RobustMethod::none && record.inlier_distance > 0.0) {
      // Outliers inflate any scale measured on all the points; the robust fit's own threshold
      // was set on the residuals of its consensus.
      record.extra["inlier_tolerance"] = robust_.threshold
                                             ? "robust_threshold, set in the config"
                                             : "2.5 x the robust fit's residual scale";
      return record.inlier_distance;
    }
    constexpr int kNeighbors = 32, kFewest = 8;
    const int k = static_cast<int>(std::min<Eigen::Index>(kNeighbors, points.cols() - 1));
    if (k < kFewest) {
      record.extra["inlier_tolerance"] =
          "3 x the fit's RMS distance (fewer than 9 points: no noise estimate)";
      return 3.0 * record.fit.rms_distance;
    }
    const double noise = normals.cols() == points.cols() ? estimateSurfaceNoise(points, normals, k)
                                                         : estimateSurfaceNoise(points, k);
    record.extra["inlier_tolerance"] = "3 x the surface noise measured from the points";
    record.extra["surface_noise"] = std::to_string(noise);
    return 3.0 * noise;
  }

  /// The robust fit of the fixed type, or with auto the library's choice (fitRobustAuto).
  FitResult robustFit(const Eigen::Matrix3Xd& points, const Eigen::Matrix3Xd& normals,
                      const Eigen::VectorXd& w, std::uint64_t seed, std::vector<char>* inliers,
                      double* limit) const {
    RobustOptions robust = robust_;
    robust.seed = seed;
    if (type_)
      return fitRobust(*type_, points, normals, w, robust, options_, inliers, limit);
    inliers->clear();
    return fitRobustAuto(points, normals, w, robust, options_, limit);
  }

  static std::string percent(int part, int whole) {
    std::ostringstream s;
    s << std::fixed << std::setprecision(1) << 100.0 * part / std::max(whole, 1) << " %";
    return s.str();
  }

  std::optional<PrimitiveType> type_;          // unset: auto
  std::optional<RobustMethod> robust_choice_;  // unset: auto
  RobustOptions robust_;                       // method resolved in prepare()
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
