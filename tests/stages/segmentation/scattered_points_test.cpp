// Outliers scattered through a scene's volume are free points after growth; recoverSmallFaces
// must not take clusters of them for small faces (phase 9, SegmentationTuning::scattered; THEORY
// §6 phase 9). Before the rule, the demo config gave the fixed scene with 10 % outliers and σ 1 %
// 193 segments for its 10 primitives: 183 of them spheres, cylinders and tori of 13–60 points, 89 %
// of their points outliers.

#include "live_regions.h"
#include "points_cloud.h"
#include "segment_cloud.h"

#include "slipfit/sampling/range_scanner.h"
#include "slipfit/sampling/scene_sampler.h"
#include "slipfit/segmentation/segmentation_kernel.h"

#include <gtest/gtest.h>
#include <pcl/point_types.h>

#include <iostream>
#include <map>
#include <string>

namespace slipfit {
namespace {

using Phase = SegmentationKernel::Phase;

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
    EXPECT_LE(testing::liveRegions(kernel), scenePrimitives().size() + 1) << what;
  }
}

// The other side of the rule: a set with no region around it is judged by its own shape, not by
// the cloud's spacing. Posts 14–20 m from a terrestrial LiDAR (radius 0.1–0.15 m, 3 m tall, no
// ground returns there beyond 80° of incidence) have returns 5–7 cm apart where the cloud's
// median spacing is about 1 cm: against that spacing every seed on them read as scattered, and
// the posts stayed unassigned. Each post must be found: one segment holds at least 99 % of its
// returns (measured 99.2–100 % on these seeds; without the rule posts 1 and 2 had none).
TEST(ScatteredPoints, FarPostsOfALidarScanAreFound) {
  SensorScene scene;
  scene.pieces.push_back(parallelogram(Eigen::Vector3d(-30, -30, 0), Eigen::Vector3d(60, 0, 0),
                                       Eigen::Vector3d(0, 60, 0)));
  const double where[3][3] = {{14.0, 0.3, 0.10}, {-17.0, 2.0, 0.12}, {3.0, 20.0, 0.15}};
  for (const auto& post : where)
    scene.pieces.push_back(
        cylinderSide(Eigen::Vector3d(post[0], post[1], 0), Eigen::Vector3d::UnitZ(), post[2], 3.0));
  scene.focus = Eigen::Vector3d::Zero();
  scene.extent = 30.0;
  RangeSensorParameters sensor;
  sensor.sensor = RangeSensorKind::lidar;
  for (std::uint64_t seed : {1u, 2u}) {
    const RangeScan scan = scanScene(scene, sensor, seed);
    std::vector<Eigen::Index> kept;
    for (Eigen::Index i = 0; i < scan.points.cols(); ++i)
      if (scan.points.col(i).allFinite())
        kept.push_back(i);
    Eigen::Matrix3Xd points(3, static_cast<Eigen::Index>(kept.size()));
    for (std::size_t j = 0; j < kept.size(); ++j)
      points.col(static_cast<Eigen::Index>(j)) = scan.points.col(kept[j]);
    const testing::SegmentedCloud out = testing::segmentCloud(testing::pointsCloud(points), 12);
    for (std::int32_t post = 1; post <= 3; ++post) {
      std::size_t returns = 0;
      std::map<std::int32_t, std::size_t> votes;
      for (std::size_t j = 0; j < kept.size(); ++j)
        if (scan.labels[static_cast<std::size_t>(kept[j])] == post) {
          ++returns;
          if (out.result.labels[j] >= 0)
            ++votes[out.result.labels[j]];
        }
      std::size_t best = 0;
      for (const auto& [label, count] : votes)
        best = std::max(best, count);
      std::cout << "seed " << seed << ", post " << post << ": " << returns << " returns, " << best
                << " in one segment\n";
      ASSERT_GT(returns, 60u) << "seed " << seed << " post " << post;
      EXPECT_GE(static_cast<double>(best), 0.99 * static_cast<double>(returns))
          << "seed " << seed << " post " << post;
    }
  }
}

}  // namespace
}  // namespace slipfit
