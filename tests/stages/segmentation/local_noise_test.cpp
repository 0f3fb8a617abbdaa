// Each point's own noise (phase 1, localNoise): a surface carrying several times the noise of the
// surface that dominates the cloud keeps a tolerance of 3 of its own σ, and holds together; on
// simulated terrestrial LiDAR scans (noise along the rays) the walls, tanks and roofs are found.
#include "points_cloud.h"
#include "segment_cloud.h"

#include "slipfit/sampling/random_vector.h"
#include "slipfit/sampling/range_scanner.h"
#include "slipfit/segmentation/segmentation_metrics.h"

#include <gtest/gtest.h>

#include <map>
#include <random>

namespace slipfit {
namespace {

/// Ground z = 0 (200 × 200 points 1 cm apart, σ = 0.8 mm across it) and a wall x = 0 standing on
/// it (100 × 50 points 2 cm apart, farther from the sensor, σ = 4 mm across it): the ground holds
/// 89 % of the points, so the cloud's lower-quartile σ̂ is the ground's. Labels: 0 ground, 1 wall.
struct TwoNoises {
  Eigen::Matrix3Xd points;
  std::vector<std::int32_t> labels;
};

TwoNoises groundAndNoisyWall(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.003, 0.003);
  std::normal_distribution<double> ground_noise(0.0, 0.0008), wall_noise(0.0, 0.004);
  TwoNoises t;
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i < 200; ++i)
    for (int j = 0; j < 200; ++j) {
      // Drawn z, y, x (randomVector's order).
      const double z = ground_noise(rng), y = 0.01 * j + jitter(rng);
      p.emplace_back(0.02 + 0.01 * i + jitter(rng), y, z);
      t.labels.push_back(0);
    }
  for (int j = 0; j < 100; ++j)
    for (int k = 0; k < 50; ++k) {
      const double z = 0.02 + 0.02 * k + jitter(rng), y = 0.02 * j + jitter(rng);
      p.emplace_back(wall_noise(rng), y, z);
      t.labels.push_back(1);
    }
  t.points.resize(3, static_cast<Eigen::Index>(p.size()));
  for (std::size_t i = 0; i < p.size(); ++i)
    t.points.col(static_cast<Eigen::Index>(i)) = p[i];
  return t;
}

// The wall's tolerance follows its own σ: the 95th percentile of the points' σ is the wall's 4 mm
// within the local estimate's error (a quantile of 128 χ²₆ estimates: ±25 % bounds it with room),
// and the wall is one plane holding ≥ 92 % of its points (measured 93.2 and 93.6 %): 3 σ keeps
// 99.7 % of a Gaussian's, less the rows nearest the ground, whose pools mix in the ground's
// samples. With the cloud's σ̂ = 0.8 mm for all (before), the wall's largest segment held 53 and 61
// points, the rest dropped as volumes or unassigned. The ground: ≥ 98 % in one plane.
TEST(LocalNoise, ANoisyWallOnAQuietGroundHoldsTogether) {
  for (unsigned seed : {1u, 2u}) {
    const TwoNoises t = groundAndNoisyWall(seed);
    const testing::SegmentedCloud out = testing::segmentCloud(testing::pointsCloud(t.points), 12);
    const SegmentationResult& r = out.result;
    EXPECT_LT(r.noise, 0.0012) << "seed " << seed << ": σ̂ is the ground's";
    EXPECT_NEAR(r.noise_range.second, 0.004, 0.001) << "seed " << seed;
    for (std::int32_t truth : {0, 1}) {
      std::map<std::int32_t, std::size_t> votes;
      std::size_t total = 0;
      for (std::size_t i = 0; i < t.labels.size(); ++i)
        if (t.labels[i] == truth) {
          ++total;
          if (r.labels[i] >= 0)
            ++votes[r.labels[i]];
        }
      std::size_t best = 0;
      std::int32_t segment = -1;
      for (const auto& [label, count] : votes)
        if (count > best) {
          best = count;
          segment = label;
        }
      ASSERT_GE(segment, 0) << "seed " << seed << " truth " << truth;
      EXPECT_EQ(r.segments[static_cast<std::size_t>(segment)].fit.type, PrimitiveType::plane);
      EXPECT_GE(static_cast<double>(best), (truth == 1 ? 0.92 : 0.98) * static_cast<double>(total))
          << "seed " << seed << " truth " << truth;
    }
  }
}

}  // namespace
}  // namespace slipfit
