#include "adapters.h"

#include "slipfit/core/name_table.h"
#include "slipfit/sampling/range_scanner.h"

#include <ostream>

namespace slipfit::pipeline::adapters {

namespace {

class ScanSamplingStage : public Stage {
 public:
  void declare(OptionSet& o) override {
    o.add("scene", setting_, kSensorSettingNames,
          "tabletop: a room corner with a table, cartons, cups, balls, cones and rings on it and "
          "larger objects on the floor; yard: a house, tanks, a silo, posts, a sand pile and "
          "tyres on 60 × 60 m of ground.");
    o.bind(p_);
    o.add("normals", normals_,
          "Keep the exact normals, facing the sensor (false: points only, as a scanner delivers "
          "them).");
  }

  void prepare() override { p_.validate(); }

  DataFlow flow() const override { return {0u, normals_ ? (kPoints | kNormals) : kPoints}; }

  void run(PointData& data, RunContext& context) override {
    const SensorScene scene = sensorScene(setting_, context.seed);
    RangeScan scan = scanScene(scene, p_, context.seed, context.threads);
    // The returns in grid order; each keeps its cell (row × width + column).
    std::vector<Eigen::Index> kept;
    for (Eigen::Index i = 0; i < scan.points.cols(); ++i)
      if (scan.points.col(i).allFinite())
        kept.push_back(i);
    const auto n = static_cast<Eigen::Index>(kept.size());
    Eigen::Matrix3Xd points(3, n), normals(3, n);
    std::vector<std::int32_t> labels(kept.size()), types(kept.size()), cells(kept.size());
    for (Eigen::Index j = 0; j < n; ++j) {
      const Eigen::Index i = kept[static_cast<std::size_t>(j)];
      points.col(j) = scan.points.col(i);
      normals.col(j) = scan.normals.col(i);
      labels[static_cast<std::size_t>(j)] = scan.labels[static_cast<std::size_t>(i)];
      types[static_cast<std::size_t>(j)] = scan.types[static_cast<std::size_t>(i)];
      cells[static_cast<std::size_t>(j)] = static_cast<std::int32_t>(i);
    }
    PointData out = sampledPointData(points, normals, normals_);
    out.setField({"truth_label", std::move(labels)});
    out.setField({"truth_type", std::move(types)});
    out.pixels = cells;
    out.setField({"grid_index", std::move(cells)});
    SensorPose pose;
    pose.origin = scan.origin;
    pose.orientation = scan.orientation;
    pose.width = static_cast<std::uint32_t>(scan.width);
    pose.height = static_cast<std::uint32_t>(scan.height);
    out.sensor = pose;
    data = std::move(out);
    context.report << "scanned " << nameIn(kSensorSettingNames, setting_) << " with "
                   << nameIn(kRangeSensorNames, p_.sensor) << ": " << data.size() << " returns of "
                   << scan.width << " × " << scan.height << " cells, " << scan.truth.size()
                   << " true primitives\n";
  }

 private:
  SensorSetting setting_ = SensorSetting::tabletop;
  RangeSensorParameters p_;
  bool normals_ = false;
};

}  // namespace

StageInfo scanSamplingInfo() {
  return {"scan_sampling",
          "a simulated range sensor (depth camera, terrestrial or airborne LiDAR) scanning a "
          "labelled scene: exact ray casting, the sensor's noise along the ray, depth levels, "
          "holes; the true label and type of each return (truth_label, truth_type) and its grid "
          "cell (grid_index)",
          [] { return std::unique_ptr<Stage>(new ScanSamplingStage); }};
}

}  // namespace slipfit::pipeline::adapters
