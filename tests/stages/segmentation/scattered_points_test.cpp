// Outliers scattered through a scene's volume are free points after growth; recoverSmallFaces
// must not take clusters of them for small faces (phase 9, SegmentationTuning::scattered; THEORY
// §6 phase 9). Before the rule, the demo config gave the fixed scene with 10 % outliers and σ 1 %
// 193 segments for its 10 primitives: 183 of them spheres, cylinders and tori of 13–60 points, 89 %
// of their points outliers.

#include "points_cloud.h"
#include "segment_cloud.h"

#include "slipfit/sampling/scene_sampler.h"
#include "slipfit/segmentation/segmentation_kernel.h"

#include <gtest/gtest.h>
#include <pcl/point_types.h>

#include <string>

namespace slipfit {
namespace {

using Phase = SegmentationKernel::Phase;

std::size_t live(const SegmentationKernel& kernel) {
  std::size_t count = 0;
  for (const auto& region : kernel.regions())
    count += region.empty() ? 0 : 1;
  return count;
}

/// The live regions of which at least half the points are outliers (true label −1).
std::size_t outlierRegions(const SegmentationKernel& kernel,
                           const std::vector<std::int32_t>& truth) {
  std::size_t count = 0;
  for (const auto& region : kernel.regions()) {
    std::size_t outliers = 0;
    for (int i : region)
      outliers += truth[static_cast<std::size_t>(i)] < 0 ? 1 : 0;
    count += !region.empty() && 2 * outliers >= region.size() ? 1 : 0;
  }
  return count;
}

// Seeds 2 and 3 (seed 1 was the scene the rule was found on). Measured: no region of mostly
// outliers after recoverSmallFaces or at the end, and 11 and 10 regions for the 10 primitives (no
// more than one extra is asserted). Without the rule
// in recoverSmallFaces it adds about 240 of them to each scene; with it there but not in
// growFreeSeeds, 6 and 0 (3 and 0 at the end: an outlier region of the second seeding round
// vouched for its neighbours).
TEST(ScatteredPoints, OutliersInTheVolumeAreNoSmallFaces) {
  for (const std::uint64_t seed : {2u, 3u}) {
    SceneSamplingParameters sp;
    sp.points = 100000;
    sp.noise = 0.01;
    sp.outlier_fraction = 0.1;
    sp.seed = seed;
    Eigen::Matrix3Xd p, n;
    std::vector<std::int32_t> truth;
    sampleScene(sp, p, n, truth);
    const auto cloud = testing::pointsCloud(p);
    const auto hoods = testing::knnNeighborhoods(cloud, 12);
    testing::estimateNormals(cloud, hoods);
    pcl::PointCloud<PointSlippage> slippage;
    LocalSlippage<pcl::PointNormal> local;
    local.setInputCloud(cloud);
    local.setNeighborhoods(hoods);
    local.compute(slippage);
    Eigen::Matrix3Xd points(3, p.cols()), normals(3, p.cols());
    std::vector<SlippageType> types;
    for (Eigen::Index i = 0; i < p.cols(); ++i) {
      const auto& q = (*cloud)[static_cast<std::size_t>(i)];
      points.col(i) = q.getVector3fMap().cast<double>();
      normals.col(i) = q.getNormalVector3fMap().cast<double>();
      types.push_back(
          static_cast<SlippageType>(slippage[static_cast<std::size_t>(i)].slippage_type));
    }
    SegmentationKernel kernel(points, normals, *hoods, types, {});
    const std::string what = "seed " + std::to_string(seed);
    kernel.runPhases(Phase::estimate_scale, Phase::recover_small_faces);
    EXPECT_EQ(outlierRegions(kernel, truth), 0u) << what << ": after recoverSmallFaces";
    kernel.runPhases(Phase::absorb_fragments, Phase::drop_non_surfaces);
    EXPECT_EQ(outlierRegions(kernel, truth), 0u) << what;
    EXPECT_LE(live(kernel), scenePrimitives().size() + 1) << what;
  }
}

}  // namespace
}  // namespace slipfit
