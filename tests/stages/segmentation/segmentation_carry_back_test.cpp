// The carry-back from an analysis sample to every input point, on a cloud ten times larger than
// its sample: a plane and a sphere, 0.2 % noise, one point per voxel (about a tenth), segmented,
// then every input point labelled.
#include "slipfit/segmentation/segmentation_carry_back.h"

#include "segment_cloud.h"
#include "shared_neighborhoods.h"

#include "slipfit/core/cloud_maps.h"
#include "slipfit/filters/subsampling.h"
#include "slipfit/sampling/primitive_sampler.h"
#include "slipfit/sampling/random_vector.h"
#include "slipfit/slippage/local_slippage.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>

namespace slipfit {
namespace {

pcl::PointCloud<pcl::PointNormal> planeAndSphere(std::vector<int>& truth) {
  PrimitiveSamplingParameters plane, sphere;
  plane.primitive = Plane{Eigen::Vector3d::UnitZ(), 0.0};
  plane.extent = 2.0;
  plane.points = 60000;
  plane.noise = 0.002;
  plane.seed = 41;
  sphere.primitive = Sphere{Eigen::Vector3d(0, 0, 1.2), 0.6};
  sphere.points = 40000;
  sphere.noise = 0.002;
  sphere.seed = 42;
  Eigen::Matrix3Xd xp, np, xs, ns;
  samplePrimitive(plane, xp, np);
  samplePrimitive(sphere, xs, ns);
  pcl::PointCloud<pcl::PointNormal> full;
  for (const auto* x : {&xp, &xs})
    for (Eigen::Index i = 0; i < x->cols(); ++i) {
      pcl::PointNormal q;
      q.getVector3fMap() = x->col(i).cast<float>();
      full.push_back(q);
      truth.push_back(x == &xp ? 0 : 1);
    }
  return full;
}

TEST(SegmentationCarryBack, EveryInputPointGetsItsPrimitivesSegment) {
  std::vector<int> truth;
  const pcl::PointCloud<pcl::PointNormal> full = planeAndSphere(truth);
  // The analysis sample: one point per voxel (the demo's), about a tenth, each input point with
  // the kept point of its voxel as representative.
  const Subsample sub = voxelSampleTo(coordinates(full), 10000);
  ASSERT_LT(sub.kept.size(), full.size() / 5);
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  for (const std::int32_t k : sub.kept)
    cloud->push_back(full[static_cast<std::size_t>(k)]);
  const testing::SegmentedCloud segmented = testing::segmentCloud(cloud, 12);
  const auto& hoods = segmented.neighborhoods;
  SegmentationResult result = segmented.result;
  ASSERT_EQ(result.segments.size(), 2u);
  const double distance_used = result.distance;

  SegmentationResult one = result, two = result;
  carrySegmentationBack(coordinates(full), sub.representative, *hoods, one, 1);
  carrySegmentationBack(coordinates(full), sub.representative, *hoods, two, 2);
  EXPECT_EQ(one.labels, two.labels);  // any thread count
  ASSERT_EQ(one.labels.size(), full.size());

  // Each true primitive maps to one segment, of its type, holding ≥ 99.9 % of its points: ε =
  // 3σ̂ + s/20 is 3.6σ here (σ̂ = 1.04σ), so a point is within ε of the sample's primitive with
  // probability 99.97 % (Gaussian σ along the normal), and every point has its voxel's kept point
  // as representative.
  for (int t = 0; t < 2; ++t) {
    std::vector<std::size_t> count(one.segments.size() + 1, 0);
    std::size_t total = 0;
    for (std::size_t i = 0; i < full.size(); ++i)
      if (truth[i] == t) {
        ++total;
        ++count[static_cast<std::size_t>(one.labels[i] + 1)];
      }
    const auto best = std::max_element(count.begin() + 1, count.end()) - count.begin() - 1;
    EXPECT_GE(static_cast<double>(count[static_cast<std::size_t>(best + 1)]),
              0.999 * static_cast<double>(total))
        << "primitive " << t;
    EXPECT_EQ(one.segments[static_cast<std::size_t>(best)].fit.type,
              t == 0 ? PrimitiveType::plane : PrimitiveType::sphere);
  }
  // Members, RMS and largest distance are the input's: RMS ≈ σ = 0.002 (the fits are the
  // sample's), and no member beyond ε.
  std::size_t members = 0;
  for (const Segment& s : one.segments) {
    members += s.indices.size();
    EXPECT_NEAR(s.rms_distance, 0.002, 0.0004);
    EXPECT_LE(s.max_distance, distance_used);
    for (int i : s.indices)
      EXPECT_GE(one.labels[static_cast<std::size_t>(i)], 0);
  }
  EXPECT_GT(members, 10 * sub.kept.size() * 9 / 10);

  // Bad input: a representative outside the sample.
  std::vector<std::int32_t> bad = sub.representative;
  bad[0] = static_cast<std::int32_t>(sub.kept.size());
  SegmentationResult three = result;
  EXPECT_THROW(carrySegmentationBack(coordinates(full), bad, *hoods, three), DegenerateInputError);
}

// The same cloud with the sample at its voxels' means (the demo's subsample): the means scatter
// less than the points, so the tolerance the sample gives understates an input point's. With
// `averaged` the carry-back re-estimates the noise on the input points and keeps them. Measured:
// the sample's σ̂ 0.38 σ (about 10 points a voxel), the re-estimate 0.998 σ; 96.4 % of the points
// assigned without it, 99.99 % with it. Asserted at those figures (fixed seeds: deterministic):
// σ̂ below 0.39 σ, the re-estimate within 1 % of σ (the median of 10⁵ distances has ~0.4 % of
// sampling error), at least 99.98 % assigned with it and under 96.5 % without.
TEST(SegmentationCarryBack, AveragedSampleTakesTheInputPointsNoise) {
  std::vector<int> truth;
  const pcl::PointCloud<pcl::PointNormal> full = planeAndSphere(truth);
  const Subsample sub = voxelSampleTo(coordinates(full), 10000);
  const RepresentedMean mean = representedMean(coordinates(full), sub);
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  for (Eigen::Index k = 0; k < mean.mean.cols(); ++k) {
    pcl::PointNormal q;
    q.getVector3fMap() = mean.mean.col(k);
    cloud->push_back(q);
  }
  const testing::SegmentedCloud segmented = testing::segmentCloud(cloud, 12);
  ASSERT_EQ(segmented.result.segments.size(), 2u);
  SegmentationResult plain = segmented.result, averaged = segmented.result;
  carrySegmentationBack(coordinates(full), sub.representative, *segmented.neighborhoods, plain);
  carrySegmentationBack(coordinates(full), sub.representative, *segmented.neighborhoods, averaged,
                        0, true);
  const auto assigned = [](const SegmentationResult& r) {
    return std::count_if(r.labels.begin(), r.labels.end(), [](std::int32_t l) { return l >= 0; });
  };
  std::cout << "sample noise " << segmented.result.noise << ", input noise " << averaged.noise
            << "; assigned " << assigned(plain) << " plain, " << assigned(averaged)
            << " averaged of " << full.size() << "\n";
  const double sigma = 0.002;
  EXPECT_LT(segmented.result.noise, 0.39 * sigma);
  EXPECT_NEAR(averaged.noise, sigma, 0.01 * sigma);
  EXPECT_NEAR(averaged.distance - segmented.result.distance,
              3.0 * (averaged.noise - segmented.result.noise), 1e-12);
  EXPECT_GE(static_cast<double>(assigned(averaged)), 0.9998 * static_cast<double>(full.size()));
  EXPECT_LT(static_cast<double>(assigned(plain)), 0.965 * static_cast<double>(full.size()));
}

// A plane z = 0 (x ≤ 0) flowing tangentially into a quarter cylinder of radius r = 0.1 (axis along
// y through (0, 0, r)), noise σ = r/20 along the normal, a point about every millimetre, voxels of
// h = 1 cm (about 100 points each), the sample labelled by the nearer primitive (as a segmentation
// of noisy points labels them: either way within the band). A fillet point at θ from the tangent
// line is r θ²/2 off the plane: alone, a point is nearer the wrong primitive with probability
// Φ(−r θ²/(4σ)), over 0.41 √(4σ/r) = 0.18 rad on either side (integrated). The mean signed
// distance of the ~1,300 input points of a representative and its 12 neighbors has σ/36 of noise:
// what is left is the points within the neighborhoods' reach (±2 h) of the line.
TEST(SegmentationCarryBack, AtATangentFilletThePointsAroundARepresentativeDecideTogether) {
  constexpr double r = 0.1, sigma = r / 20, length = 0.2;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, sigma);
  pcl::PointCloud<pcl::PointNormal> full;
  std::vector<int> truth;
  const auto add = [&](const Eigen::Vector3d& p, int label) {
    pcl::PointNormal q;
    q.getVector3fMap() = p.cast<float>();
    full.push_back(q);
    truth.push_back(label);
  };
  for (int i = 0; i < 20000; ++i) {  // the plane, 0.1 × 0.2; drawn z, y, x (randomVector's order)
    const double z = noise(rng), y = length * unit(rng);
    add(Eigen::Vector3d(-0.1 * unit(rng), y, z), 0);
  }
  for (int i = 0; i < 31416; ++i) {  // the quarter cylinder, 0.157 × 0.2
    const double phi = M_PI / 2 * unit(rng), rho = r + noise(rng);
    add(Eigen::Vector3d(rho * std::sin(phi), length * unit(rng), r - rho * std::cos(phi)), 1);
  }
  const Subsample sub = voxelSample(coordinates(full), 0.01);
  auto sample = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  for (const std::int32_t k : sub.kept)
    sample->push_back(full[static_cast<std::size_t>(k)]);
  // Neighborhoods of 40 sample points reach about 3.6 h = 0.018 from a point: as far as the band.
  const std::shared_ptr<Neighborhoods> hoods = testing::knnNeighborhoods(sample, 12);
  // The sample's segmentation: the true primitives, each kept point labelled by the nearer (as
  // the kernel labels noisy points: within the band either way).
  SegmentationResult result;
  result.segments.resize(2);
  result.segments[0].fit.type = PrimitiveType::plane;
  result.segments[0].fit.refined = Plane{Eigen::Vector3d::UnitZ(), 0.0};
  result.segments[1].fit.type = PrimitiveType::cylinder;
  result.segments[1].fit.refined = Cylinder{Eigen::Vector3d::UnitY(), Eigen::Vector3d(0, 0, r), r};
  for (const std::int32_t k : sub.kept) {
    const Eigen::Vector3d p = full[static_cast<std::size_t>(k)].getVector3fMap().cast<double>();
    result.labels.push_back(distance(p, result.segments[0].fit.refined) <=
                                    distance(p, result.segments[1].fit.refined)
                                ? 0
                                : 1);
  }
  result.noise = sigma;
  result.distance = 5 * sigma;
  result.max_angle = M_PI / 6;  // the default: ties only where the normals are within 30°
  const std::vector<Primitive> primitives{result.segments[0].fit.refined,
                                          result.segments[1].fit.refined};
  const std::vector<std::int32_t> sample_labels = result.labels;
  carrySegmentationBack(coordinates(full), sub.representative, *hoods, result, 1);
  // The rule of each point alone: the nearer primitive, of those around its representative.
  std::size_t wrong = 0, wrong_alone = 0;
  for (std::size_t i = 0; i < full.size(); ++i) {
    const Eigen::Vector3d p = full[i].getVector3fMap().cast<double>();
    const auto r = static_cast<std::size_t>(sub.representative[i]);
    bool both = false;
    for (pcl::index_t j : (*hoods)[r])
      both = both || sample_labels[static_cast<std::size_t>(j)] != sample_labels[r];
    const int nearest = !both ? sample_labels[r]
                        : distance(p, primitives[0]) <= distance(p, primitives[1]) ? 0
                                                                                   : 1;
    wrong_alone += nearest != truth[i] ? 1 : 0;
    ASSERT_GE(result.labels[i], 0) << "point " << i << " is within 5σ of its primitive";
    wrong += result.labels[i] != truth[i] ? 1 : 0;
  }
  // Per point alone: 2 sides × 0.18 r × 0.2 m at 10⁶ points/m² ≈ 7,300 points (measured 7,356);
  // together at most half of that (measured 3,190: 0.43).
  std::cout << "[ figures  ] wrong labels at the fillet: " << wrong
            << " (each point alone: " << wrong_alone << ")\n";
  EXPECT_GT(wrong_alone, 6500u);
  EXPECT_LT(static_cast<double>(wrong), 0.5 * static_cast<double>(wrong_alone));
}

}  // namespace
}  // namespace slipfit
