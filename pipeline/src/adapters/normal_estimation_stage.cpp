#include "adapters.h"

#include "slipfit/core/name_table.h"
#include "slipfit/neighborhoods/normal_estimation.h"
#include "slipfit/pipeline/errors.h"

#include <ostream>

namespace slipfit::pipeline::adapters {

namespace {

enum class FailedNormals { drop, error };
constexpr std::array<std::pair<FailedNormals, std::string_view>, 2> kFailedNormalsNames{{
    {FailedNormals::drop, "drop"},
    {FailedNormals::error, "error"},
}};

class NormalEstimationStage : public Stage {
 public:
  void declare(OptionSet& o) override {
    o.bind(p_);
    o.add("use_shared", use_shared_,
          "Use the neighborhoods of an earlier neighborhood_selection stage when there is one "
          "(no second search).");
    o.add("keep_input", keep_input_,
          "When the input has normals, keep them as they are and estimate nothing.");
    o.add("failed", failed_, kFailedNormalsNames,
          "Points whose normal cannot be estimated (fewer than 3 neighbors): drop them, or stop "
          "with an error. More than half of the points without a normal is an error either way.");
  }

  void prepare() override { p_.validate(); }

  DataFlow flow() const override {
    // Reference orientation reads the input's normals; keep_input may use them if present.
    return {p_.orientation == NormalOrientation::reference ? (kPoints | kNormals) : kPoints,
            kNormals};
  }

  void run(PointData& data, RunContext& context) override {
    if (keep_input_ && data.has_normals) {
      context.report << "normals: kept the input's " << data.size() << " normals\n";
      return;
    }
    NormalParameters p = p_;
    p.threads = context.threads;
    // 'sensor': PCL's convention, towards the cloud's sensor_origin_, which the input's sensor
    // pose sets; an input without one (a PLY, an unorganized PCD at the identity) falls back to
    // the viewpoint, and the report says which.
    const bool from_sensor = p.orientation == NormalOrientation::sensor && data.sensor;
    if (p.orientation == NormalOrientation::sensor && !from_sensor)
      p.orientation = NormalOrientation::viewpoint;
    if (from_sensor)
      data.cloud->sensor_origin_ << data.sensor->origin.cast<float>(), 0.0f;
    OrientedNormalEstimation<pcl::PointNormal, pcl::Normal> estimation;
    estimation.setParameters(p);
    estimation.setInputCloud(data.cloud);
    const bool shared = use_shared_ && data.neighborhoods;
    if (shared)
      estimation.setNeighborhoods(data.neighborhoods);
    if (p.orientation == NormalOrientation::reference) {
      auto reference = std::make_shared<Eigen::Matrix3Xf>(normals(std::as_const(*data.cloud)));
      estimation.setReferenceNormals(std::move(reference));
    }
    pcl::PointCloud<pcl::Normal> out;
    estimation.compute(out);
    const auto& st = estimation.statistics();
    if (st.failed > 0 && failed_ == FailedNormals::error)
      throw RunError(std::to_string(st.failed) +
                     " points have no normal (fewer than 3 neighbors or non-finite)");
    // Dropping is for the odd isolated point; a neighborhood setting that leaves most points
    // without a normal is a mistake to report, not a cloud to shrink silently.
    if (2 * st.failed > data.size())
      throw RunError(std::to_string(st.failed) + " of " + std::to_string(data.size()) +
                     " points have no normal (fewer than 3 neighbors or non-finite): more than "
                     "half would be dropped; check k or radius");

    auto& cloud = *data.cloud;
    std::vector<char> keep(cloud.size(), 1);
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      cloud[i].getNormalVector3fMap() = out[i].getNormalVector3fMap();
      cloud[i].curvature = out[i].curvature;
      keep[i] = out[i].getNormalVector3fMap().allFinite() ? 1 : 0;
    }
    data.has_normals = true;
    data.has_curvature = true;
    if (st.failed > 0)
      data.keepOnly(keep);
    if (data.size() == 0)
      throw RunError("no point has a normal");

    context.report << "normals: " << st.estimated << " estimated from "
                   << (shared     ? "the shared neighborhoods"
                       : p.radius ? "a radius search"
                                  : "a kNN search")
                   << ", " << st.failed << " failed" << (st.failed ? " (dropped)" : "")
                   << ", orientation " << orientationName();
    if (from_sensor) {
      const Eigen::Vector3d at = data.sensor->origin + data.frame.shift;
      context.report << " (towards the input's sensor at (" << at.x() << ", " << at.y() << ", "
                     << at.z() << "))";
    } else if (p_.orientation == NormalOrientation::sensor) {
      const Eigen::Vector3f at = p.viewpoint.value_or(Eigen::Vector3f::Zero());
      context.report << " (the input has no sensor pose: towards the viewpoint (" << at.x() << ", "
                     << at.y() << ", " << at.z() << "))";
    }
    if (p.orientation == NormalOrientation::reference)
      context.report << " (" << st.flipped << " flipped)";
    if (p.orientation == NormalOrientation::consistent)
      context.report << " (" << st.flipped << " flipped, " << st.components << " components)";
    context.report << "\n";
  }

 private:
  std::string_view orientationName() const {
    return nameIn(kNormalOrientationNames, p_.orientation);
  }

  NormalParameters p_;
  bool use_shared_ = true;
  bool keep_input_ = false;
  FailedNormals failed_ = FailedNormals::drop;
};

}  // namespace

StageInfo normalEstimationInfo() {
  return {"normal_estimation",
          "oriented normals by PCL NormalEstimationOMP on shared or own neighborhoods",
          [] { return std::unique_ptr<Stage>(new NormalEstimationStage); }};
}

}  // namespace slipfit::pipeline::adapters
