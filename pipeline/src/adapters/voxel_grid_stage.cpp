#include "adapters.h"
#include "point_filter.h"

#include "slipfit/filters/point_filters.h"

#include <vector>

namespace slipfit::pipeline::adapters {

StageInfo voxelGridInfo() {
  return {"voxel_grid",
          "one point per voxel (PCL's UniformSampling or VoxelGrid): the others are absent from "
          "every output",
          [] {
            return std::unique_ptr<Stage>(new FilterStage<VoxelGridParameters>(
                "voxel_grid", [](const PointData& data, const VoxelGridParameters& p,
                                 std::vector<Eigen::Vector3f>& centroids) {
                  return voxelGrid(data.cloud, p, centroids);
                }));
          }};
}

}  // namespace slipfit::pipeline::adapters
