#include "adapters.h"
#include "point_filter.h"

#include "slipfit/point_filters.h"

#include <vector>

namespace slipfit::pipeline::adapters {

namespace {

/// One point per voxel of edge `leaf`: PCL's UniformSampling (the input point nearest the voxel's
/// centre) or VoxelGrid (the voxel's centroid).
class VoxelGridStage : public Stage {
 public:
  void declare(OptionSet& o) override { o.bind(p_); }
  void prepare() override { p_.validate(); }
  DataFlow flow() const override { return {kPoints, 0u}; }

  void run(PointData& data, RunContext& context) override {
    requireInputCloud(data);
    std::vector<Eigen::Vector3f> centroids;
    keepFiltered(data, voxelGrid(data.cloud, p_, centroids), context, "voxel_grid");
    for (std::size_t k = 0; k < centroids.size(); ++k)
      (*data.cloud)[k].getVector3fMap() = centroids[k];
  }

 private:
  VoxelGridParameters p_;
};

}  // namespace

StageInfo voxelGridInfo() {
  return {"voxel_grid",
          "one point per voxel (PCL's UniformSampling or VoxelGrid): the others are absent from "
          "every output",
          [] { return std::unique_ptr<Stage>(new VoxelGridStage); }};
}

}  // namespace slipfit::pipeline::adapters
