// Phase 13 (join_occluded_pieces, issue 34): on a sensor's frame, two pieces of one surface that an
// occluder cut apart are one segment; two parallel surfaces a few σ apart, two pieces further apart
// than they are wide, and two coplanar faces of a noise-free (CAD) cloud stay apart.
#include "segment_cloud.h"

#include <gtest/gtest.h>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cstddef>
#include <random>
#include <set>

namespace slipfit {
namespace {

constexpr double kSpacing = 0.01;

/// Two square patches of the plane z = 0 on a grid of kSpacing, x in [0, width) and
/// [width + gap, 2 width + gap), y in [0, 0.4); the second raised by \a offset; Gaussian noise
/// \a sigma along z.
pcl::PointCloud<pcl::PointNormal>::Ptr twoPieces(double width, double gap, double offset,
                                                 double sigma) {
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, sigma);
  const auto columns = static_cast<int>(width / kSpacing + 0.5);
  for (int piece = 0; piece < 2; ++piece)
    for (int u = 0; u < columns; ++u)
      for (int v = 0; v < 40; ++v) {
        pcl::PointNormal p;
        p.x = static_cast<float>(piece * (width + gap) + u * kSpacing);
        p.y = static_cast<float>(v * kSpacing);
        p.z = static_cast<float>(piece * offset + (sigma > 0.0 ? noise(rng) : 0.0));
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

// σ = 2 mm on a 1 cm grid (σ̂ ≥ s/20: a sensor's noise). Pieces 0.3 m wide, 0.2 m apart.
constexpr double kSigma = 0.002;

TEST(OccludedPieces, TwoPiecesOfOneNoisyPlaneAreOneSegment) {
  const auto cloud = twoPieces(0.3, 0.2, 0.0, kSigma);
  const SegmentationResult r = testing::segmentCloud(cloud, 12).result;
  // Without the phase: two planes of 1200 points each.
  EXPECT_EQ(largeSegments(r, cloud->size()), 1u);
  EXPECT_GE(largestShare(r, cloud->size()), 0.99);
}

TEST(OccludedPieces, TwoParallelPlanesSixSigmaApartStayTwo) {
  // Each piece's plane, extended, misses the other by 6 σ (3 × the union's noise ratio of 2).
  const auto cloud = twoPieces(0.3, 0.2, 6.0 * kSigma, kSigma);
  const SegmentationResult r = testing::segmentCloud(cloud, 12).result;
  EXPECT_EQ(largeSegments(r, cloud->size()), 2u);
}

TEST(OccludedPieces, PiecesFurtherApartThanTheyAreWideStayTwo) {
  // Pieces 0.1 m wide (0.41 m across their diagonal) 0.5 m apart: two faces that happen to be
  // coplanar, not one surface behind an occluder.
  const auto cloud = twoPieces(0.1, 0.5, 0.0, kSigma);
  const SegmentationResult r = testing::segmentCloud(cloud, 12).result;
  EXPECT_EQ(largeSegments(r, cloud->size()), 2u);
}

TEST(OccludedPieces, CoplanarFacesOfANoiseFreeCloudStayTwo) {
  // No noise: a CAD part's two coplanar faces are two segments (Fit4CAD's ground truth).
  const auto cloud = twoPieces(0.3, 0.2, 0.0, 0.0);
  const SegmentationResult r = testing::segmentCloud(cloud, 12).result;
  EXPECT_EQ(largeSegments(r, cloud->size()), 2u);
}

}  // namespace
}  // namespace slipfit
