// Phase 13 (join_occluded_pieces, issue 34): on a sensor's frame (depth on levels, or a cloud
// with a sensor pose), two pieces of one surface that an occluder cut apart are one segment; two
// parallel surfaces a few σ apart and two pieces further apart than they are wide stay apart, and
// so do two coplanar faces of a cloud with neither levels nor a sensor pose, noise-free (a CAD
// part) or noisy (a sparse CAD part's σ̂ reaches s/20).
#include "segment_cloud.h"
#include "slipfit/neighborhoods/depth_quantization.h"

#include <gtest/gtest.h>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cmath>
#include <cstddef>
#include <random>
#include <set>

namespace slipfit {
namespace {

constexpr double kSpacing = 0.01;
// The pieces lie on the plane z = kTilt·x, seen along z (the depth axis): a floor seen at a slant.
constexpr double kTilt = 0.3;

/// Two patches of the plane z = kTilt·x, one point per kSpacing cell jittered within it, x in
/// [0, width) and [width + gap, 2 width + gap), y in [0, 0.4); the second raised by \a offset;
/// Gaussian noise \a sigma along z, then z rounded to levels \a step apart where \a step > 0
/// (a depth camera's: 0.25 m of depth on levels 5 mm apart, 20 or more points on each).
pcl::PointCloud<pcl::PointNormal>::Ptr twoPieces(double width, double gap, double offset,
                                                 double sigma, double step) {
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, sigma);
  std::uniform_real_distribution<double> jitter(-0.4, 0.4);
  const auto columns = static_cast<int>(width / kSpacing + 0.5);
  for (int piece = 0; piece < 2; ++piece)
    for (int u = 0; u < columns; ++u)
      for (int v = 0; v < 40; ++v) {
        const double du = jitter(rng);
        const double dv = jitter(rng);
        const double x = piece * (width + gap) + (u + du) * kSpacing;
        const double e = sigma > 0.0 ? noise(rng) : 0.0;
        double z = kTilt * x + piece * offset + e;
        if (step > 0.0)
          z = step * std::round(z / step);
        pcl::PointNormal p;
        p.x = static_cast<float>(x);
        p.y = static_cast<float>((v + dv) * kSpacing);
        p.z = static_cast<float>(z);
        cloud->push_back(p);
      }
  return cloud;
}

/// The number of segments holding at least a tenth of the points.
std::size_t largeSegments(const SegmentationResult& r, std::size_t points) {
  std::size_t count = 0;
  for (const auto& s : r.segments)
    count += 10 * s.indices.size() >= points ? 1 : 0;
  return count;
}

/// The share of the points in the largest segment, which must be a plane.
double largestShare(const SegmentationResult& r, std::size_t points) {
  EXPECT_FALSE(r.segments.empty());
  if (r.segments.empty())
    return 0.0;
  EXPECT_EQ(r.segments[0].fit.type, PrimitiveType::plane);
  return static_cast<double>(r.segments[0].indices.size()) / static_cast<double>(points);
}

// σ = 2 mm on a 1 cm grid, depth on levels 5 mm apart (2.5 σ, as a disparity sensor's: levels
// finer than 1.5 σ are part of the noise, T::fine_levels). Pieces 0.3 m wide, 0.2 m apart.
constexpr double kSigma = 0.002;
constexpr double kStep = 0.005;

TEST(OccludedPieces, TwoPiecesOfOneFramesPlaneAreOneSegment) {
  const auto cloud = twoPieces(0.3, 0.2, 0.0, kSigma, kStep);
  const SegmentationResult r = testing::segmentCloud(cloud, 12).result;
  ASSERT_TRUE(r.lattice.detected());
  EXPECT_EQ(r.lattice.axis, 2);
  // Without the phase: two planes of 1200 points each.
  EXPECT_EQ(largeSegments(r, cloud->size()), 1u);
  EXPECT_GE(largestShare(r, cloud->size()), 0.99);
}

TEST(OccludedPieces, TwoParallelPlanesSixSigmaApartStayTwo) {
  // Each piece's plane, extended, misses the other by 6 σ (3 × the union's noise ratio of 2;
  // rounding to 5 mm levels adds σ = 1.4 mm).
  const auto cloud = twoPieces(0.3, 0.2, 6.0 * kSigma, kSigma, kStep);
  const SegmentationResult r = testing::segmentCloud(cloud, 12).result;
  ASSERT_TRUE(r.lattice.detected());
  EXPECT_EQ(largeSegments(r, cloud->size()), 2u);
}

TEST(OccludedPieces, PiecesFurtherApartThanTheyAreWideStayTwo) {
  // Pieces 0.3 m wide (0.5 m across their diagonal) 0.6 m apart: two faces that happen to be
  // coplanar, not one surface behind an occluder.
  const auto cloud = twoPieces(0.3, 0.6, 0.0, kSigma, kStep);
  const SegmentationResult r = testing::segmentCloud(cloud, 12).result;
  ASSERT_TRUE(r.lattice.detected());
  EXPECT_EQ(largeSegments(r, cloud->size()), 2u);
}

TEST(OccludedPieces, CoplanarFacesOfANoiseFreeCloudStayTwo) {
  // No noise: a CAD part's two coplanar faces are two segments (Fit4CAD's ground truth).
  const auto cloud = twoPieces(0.3, 0.2, 0.0, 0.0, 0.0);
  const SegmentationResult r = testing::segmentCloud(cloud, 12).result;
  EXPECT_EQ(largeSegments(r, cloud->size()), 2u);
}

TEST(OccludedPieces, CoplanarFacesOfANoisyCloudWithoutLevelsStayTwo) {
  // σ̂ ≥ s/20 but no levels: noise alone does not make a sensor's frame (Fit4CAD's sparse PC113
  // reads σ̂ ≥ s/20; its two coaxial cylinders of one radius are two faces).
  const auto cloud = twoPieces(0.3, 0.2, 0.0, kSigma, 0.0);
  const SegmentationResult r = testing::segmentCloud(cloud, 12).result;
  ASSERT_FALSE(r.lattice.detected());
  EXPECT_EQ(largeSegments(r, cloud->size()), 2u);
}

TEST(OccludedPieces, LevelsFinerThanTheNoiseAreNotASensorsLevels) {
  // Depth stored on levels as far apart as the noise (2 mm under σ = 2 mm; depth stored in
  // millimetres under a time-of-flight camera's noise at range is finer still): a lattice, which
  // detectQuantizedAxis finds, but whose rounding (σ 0.58 mm, 8 % of the variance) is part of
  // the noise. Not modelled as a disparity sensor's levels (those are 2–3 σ apart): the cloud is
  // read as one without levels, and its coplanar faces stay two, as
  // CoplanarFacesOfANoisyCloudWithoutLevelsStayTwo's.
  const auto cloud = twoPieces(0.3, 0.2, 0.0, kSigma, kSigma);
  Eigen::Matrix3Xd xyz(3, static_cast<Eigen::Index>(cloud->size()));
  for (std::size_t i = 0; i < cloud->size(); ++i)
    xyz.col(static_cast<Eigen::Index>(i)) = (*cloud)[i].getVector3fMap().cast<double>();
  ASSERT_TRUE(detectQuantizedAxis(xyz).detected());
  const SegmentationResult r = testing::segmentCloud(cloud, 12).result;
  EXPECT_FALSE(r.lattice.detected());
  EXPECT_EQ(largeSegments(r, cloud->size()), 2u);
}

TEST(OccludedPieces, PiecesOfASensorsViewWithoutLevelsAreOneSegment) {
  // The same noisy cloud with a sensor pose (PCL's sensor_origin_, as a LiDAR scan's PCD carries
  // its VIEWPOINT): a sensor's view, so the pieces an occluder cut apart are joined.
  const auto cloud = twoPieces(0.3, 0.2, 0.0, kSigma, 0.0);
  cloud->sensor_origin_ = Eigen::Vector4f(0.4f, 0.2f, 3.0f, 0.0f);
  const SegmentationResult r = testing::segmentCloud(cloud, 12).result;
  ASSERT_FALSE(r.lattice.detected());
  EXPECT_EQ(largeSegments(r, cloud->size()), 1u);
  EXPECT_GE(largestShare(r, cloud->size()), 0.99);
}

TEST(OccludedPieces, ParallelPlanesOfASensorsViewSixSigmaApartStayTwo) {
  const auto cloud = twoPieces(0.3, 0.2, 6.0 * kSigma, kSigma, 0.0);
  cloud->sensor_origin_ = Eigen::Vector4f(0.4f, 0.2f, 3.0f, 0.0f);
  const SegmentationResult r = testing::segmentCloud(cloud, 12).result;
  EXPECT_EQ(largeSegments(r, cloud->size()), 2u);
}

}  // namespace
}  // namespace slipfit
