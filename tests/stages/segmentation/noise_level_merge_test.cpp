// Posts seen by a depth camera at 1.6–2.4 m: narrow cylinders (radius 2.5–4 cm) whose depth
// noise (σ 3–5 mm along the ray) and disparity levels (8–17 mm apart) are a tenth of their
// radius. Their face towards the camera grows as a plane and their flanks as cylinders; the
// crease rule (planes more than α apart) and, once settled, BIC (which takes the rounding to
// levels, correlated along the surface, for independent noise) kept the strips apart: on the
// simulated far frame of seed 1 a post came out as a plane and two cylinders (IoU 0.375).
// explainsWithinNoise (THEORY §6 phase 4) merges two regions that one primitive explains within
// their own noise, when neither is four times the other (a region that small moves the union's
// RMS too little to tell). Measured on seeds 1–3: each of the 9 posts is a cylinder segment
// holding at least 0.977 of its returns (7 of them 0.99); before the rule 4 of the 9 were split
// in 4 or 5 segments, the largest holding 0.40–0.44.
#include "points_cloud.h"
#include "segment_cloud.h"
#include "slipfit/sampling/range_scanner.h"
#include "slipfit/sampling/surface_piece.h"

#include <gtest/gtest.h>

#include <iostream>
#include <map>

namespace slipfit {
namespace {

TEST(NoiseLevelMerge, PostsOfADepthFrameAreOneCylinderEach) {
  SensorScene scene;
  scene.pieces.push_back(parallelogram(Eigen::Vector3d(-3, -3, 0), Eigen::Vector3d(6, 0, 0),
                                       Eigen::Vector3d(0, 6, 0)));
  const double where[3][3] = {{-0.35, 0.0, 0.025}, {0.0, 0.25, 0.03}, {0.4, -0.1, 0.04}};
  for (const auto& post : where)
    scene.pieces.push_back(
        cylinderSide(Eigen::Vector3d(post[0], post[1], 0), Eigen::Vector3d::UnitZ(), post[2], 0.7));
  scene.focus = Eigen::Vector3d(0, 0, 0.35);
  scene.extent = 3.0;
  RangeSensorParameters sensor;
  sensor.distance_min = 1.6;
  sensor.distance_max = 2.4;
  for (std::uint64_t seed : {1u, 2u, 3u}) {
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
      std::int32_t best = -1;
      for (const auto& [label, count] : votes)
        if (best < 0 || count > votes[best])
          best = label;
      ASSERT_GE(best, 0) << "seed " << seed << " post " << post << ": no segment";
      std::cout << "seed " << seed << ", post " << post << ": " << returns << " returns, "
                << votes[best] << " in one segment of " << votes.size() << "\n";
      ASSERT_GT(returns, 300u) << "seed " << seed << " post " << post;
      EXPECT_EQ(out.result.segments[static_cast<std::size_t>(best)].fit.type,
                PrimitiveType::cylinder)
          << "seed " << seed << " post " << post;
      EXPECT_GE(static_cast<double>(votes[best]), 0.977 * static_cast<double>(returns))
          << "seed " << seed << " post " << post;
    }
  }
}

}  // namespace
}  // namespace slipfit
