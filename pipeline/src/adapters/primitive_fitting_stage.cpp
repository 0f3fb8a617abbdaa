#include "adapters.h"

#include "slipfit/core/cloud_maps.h"
#include "slipfit/fitting/labelled_fitting.h"
#include "slipfit/pipeline/errors.h"
#include "slipfit/pipeline/output_files.h"
#include "slipfit/pipeline/primitives_report.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <memory>
#include <ostream>
#include <sstream>
#include <utility>
#include <vector>

namespace slipfit::pipeline::adapters {

namespace {

/// Below this share of the points a fit is reported as not describing the cloud.
constexpr double kFewInliers = 0.5;

class PrimitiveFittingStage : public Stage {
 public:
  void declare(OptionSet& o) override {
    o.bind(p_, {{"threshold", "robust_threshold"}});
    o.add("labels", labels_,
          "Integer per-point field: fit one primitive per label >= 0 (unset: the whole cloud).");
    o.add("weights", weights_, "Per-point field of non-negative weights (unset: all 1).");
    o.add("report", report_, "File name of the YAML report in the output dir.").fileName();
  }

  DataFlow flow() const override {
    const bool normals =
        p_.type && (*p_.type == PrimitiveType::cylinder || *p_.type == PrimitiveType::cone ||
                    *p_.type == PrimitiveType::torus);
    return {normals ? (kPoints | kNormals) : kPoints, 0u};
  }

  std::vector<std::string> outputFiles() const override { return {report_}; }

  void prepare() override { p_.validate(); }

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
    std::vector<double> labels;
    if (!labels_.empty()) {
      labels = data.numericField(labels_);
      if (labels.size() != n)
        throw RunError("no per-point field '" + labels_ + "' for the labels");
    }
    // The PCL front end, called as a PCL application calls it.
    LabelledFitting<pcl::PointNormal> fitting;
    fitting.setInputCloud(data.cloud);
    if (data.has_normals)
      fitting.setInputNormals(data.cloud);
    fitting.setWeights(std::make_shared<const std::vector<double>>(std::move(weights)));
    if (!labels_.empty())
      fitting.setLabels(std::make_shared<const std::vector<double>>(std::move(labels)));
    fitting.setParameters(p_);
    fitting.setSeed(context.seed);
    LabelledFits fits;
    fitting.compute(fits);
    const bool ransac = p_.robustMethod(labels_.empty()) == RobustMethod::ransac;
    std::vector<PrimitiveRecord> records;
    for (LabelledFit& f : fits.fits) {
      if (!f.fit.ok() && !f.label)
        throw RunError(f.fit.reason);
      records.push_back(record(std::move(f), records.size(), ransac));
    }
    data.setField({"fit_distance", std::move(fits.distance)});
    printSummary(records, context);
    if (!context.outputs)
      throw RunError("no output directory for the report");
    context.outputs->addText(report_, primitivesYaml(records, data_source_, data.frame.shift));
  }

 private:
  static PrimitiveRecord record(LabelledFit f, std::size_t id, bool ransac) {
    PrimitiveRecord r;
    r.id = static_cast<int>(id);
    r.label = f.label;
    r.fit = std::move(f.fit);
    r.inlier_distance = f.inlier_distance;
    if (!r.fit.ok())
      return r;
    r.inliers = static_cast<std::size_t>(f.inliers);
    r.extra["inlier_tolerance"] = f.tolerance_source;
    if (f.surface_noise)
      r.extra["surface_noise"] = std::to_string(*f.surface_noise);
    r.extra["points"] = std::to_string(f.points);
    if (f.inliers < kFewInliers * f.points)
      r.extra["warning"] = "only " + percent(f.inliers, f.points) +
                           " of the points are inliers: the " +
                           (f.label ? std::string("label") : "cloud") + " is not one " +
                           std::string(primitiveTypeName(r.fit.type)) +
                           (ransac ? "" : " (robust: ransac finds the largest one)");
    return r;
  }

  void printSummary(const std::vector<PrimitiveRecord>& records, RunContext& context) const {
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
  }

  static std::string percent(int part, int whole) {
    std::ostringstream s;
    s << std::fixed << std::setprecision(1) << 100.0 * part / std::max(whole, 1) << " %";
    return s.str();
  }

  LabelledFitParameters p_;
  std::string labels_, weights_;
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
