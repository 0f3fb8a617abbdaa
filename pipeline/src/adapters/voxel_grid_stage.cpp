#include "adapters.h"
#include "point_filter.h"

#include "slipfit/pipeline/errors.h"

#include <pcl/common/common.h>
#include <pcl/filters/uniform_sampling.h>
#include <pcl/filters/voxel_grid.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace slipfit::pipeline::adapters {

namespace {

enum class Method { uniform, centroid };
constexpr std::array<std::pair<Method, std::string_view>, 2> kMethodNames{{
    {Method::uniform, "uniform"},
    {Method::centroid, "centroid"},
}};

/// One point per voxel of edge `leaf`: PCL's UniformSampling (the input point nearest the voxel's
/// centre) or VoxelGrid (the voxel's centroid).
class VoxelGridStage : public Stage {
 public:
  void declare(OptionSet& o) override {
    o.add("leaf", leaf_, "Voxel edge.").unit("cloud units").above(0).required();
    o.add("method", method_, kMethodNames,
          "uniform: each voxel keeps its input point nearest the voxel's centre, with all its "
          "fields (PCL's UniformSampling); centroid: the point moves to the centroid of its "
          "voxel's points (PCL's VoxelGrid), the other fields those of the voxel's point nearest "
          "the centroid.");
  }

  DataFlow flow() const override { return {kPoints, 0u}; }

  void run(PointData& data, RunContext& context) override {
    requireInputCloud(data);
    checkGrid(data);
    const std::string why = "one per voxel of " + std::to_string(leaf_) + ", " +
                            std::string(kMethodNames[static_cast<std::size_t>(method_)].second);
    if (method_ == Method::uniform) {
      pcl::UniformSampling<pcl::PointNormal> sampling(true);
      sampling.setInputCloud(data.cloud);
      sampling.setRadiusSearch(leaf_);
      pcl::PointCloud<pcl::PointNormal> kept_points;
      sampling.filter(kept_points);
      std::vector<char> removed(data.size(), 0);
      for (const auto i : *sampling.getRemovedIndices())
        removed[static_cast<std::size_t>(i)] = 1;
      pcl::Indices kept;
      for (std::size_t i = 0; i < data.size(); ++i)
        if (!removed[i])
          kept.push_back(static_cast<pcl::index_t>(i));
      keepFiltered(data, kept, context, "voxel_grid", why);
      return;
    }
    pcl::VoxelGrid<pcl::PointNormal> grid;
    grid.setInputCloud(data.cloud);
    grid.setLeafSize(static_cast<float>(leaf_), static_cast<float>(leaf_),
                     static_cast<float>(leaf_));
    grid.setSaveLeafLayout(true);
    pcl::PointCloud<pcl::PointNormal> centroids;
    grid.filter(centroids);
    // Each voxel's input point nearest its centroid stands for it.
    const std::size_t m = centroids.size();
    std::vector<pcl::index_t> nearest(m, -1);
    std::vector<float> best(m, std::numeric_limits<float>::max());
    const auto& cloud = *data.cloud;
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      const int v = grid.getCentroidIndex(cloud[i]);
      if (v < 0 || static_cast<std::size_t>(v) >= m)
        continue;
      const float d =
          (cloud[i].getVector3fMap() - centroids[static_cast<std::size_t>(v)].getVector3fMap())
              .squaredNorm();
      if (d < best[static_cast<std::size_t>(v)]) {
        best[static_cast<std::size_t>(v)] = d;
        nearest[static_cast<std::size_t>(v)] = static_cast<pcl::index_t>(i);
      }
    }
    pcl::Indices kept;
    for (std::size_t v = 0; v < m; ++v)
      if (nearest[v] >= 0)
        kept.push_back(nearest[v]);
    std::sort(kept.begin(), kept.end());
    std::vector<int> voxel(cloud.size(), -1);
    for (std::size_t v = 0; v < m; ++v)
      if (nearest[v] >= 0)
        voxel[static_cast<std::size_t>(nearest[v])] = static_cast<int>(v);
    std::vector<Eigen::Vector3f> at;
    at.reserve(kept.size());
    for (const auto i : kept)
      at.push_back(
          centroids[static_cast<std::size_t>(voxel[static_cast<std::size_t>(i)])].getVector3fMap());
    keepFiltered(data, kept, context, "voxel_grid", why);
    for (std::size_t k = 0; k < at.size(); ++k)
      (*data.cloud)[k].getVector3fMap() = at[k];
  }

 private:
  /// PCL's grids index voxels with 32-bit integers and, when they would overflow, warn and
  /// return the cloud unchanged: say so instead.
  void checkGrid(const PointData& data) const {
    pcl::PointNormal lo, hi;
    pcl::getMinMax3D(*data.cloud, lo, hi);
    double voxels = 1.0;
    for (int a = 0; a < 3; ++a)
      voxels *= std::floor((hi.getVector3fMap()[a] - lo.getVector3fMap()[a]) / leaf_) + 1.0;
    if (voxels > static_cast<double>(std::numeric_limits<std::int32_t>::max()))
      throw RunError("leaf " + std::to_string(leaf_) + " gives " + std::to_string(voxels) +
                     " voxels over the cloud's extent, more than PCL's grid can index (2^31); "
                     "use a larger leaf");
  }

  double leaf_ = 0.0;
  Method method_ = Method::uniform;
};

}  // namespace

StageInfo voxelGridInfo() {
  return {"voxel_grid",
          "one point per voxel (PCL's UniformSampling or VoxelGrid): the others are absent from "
          "every output",
          [] { return std::unique_ptr<Stage>(new VoxelGridStage); }};
}

}  // namespace slipfit::pipeline::adapters
