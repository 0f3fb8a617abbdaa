#include "slipfit/slippage/local_slippage.h"

#include "shapes.h"
#include "shared_neighborhoods.h"
#include "slipfit/core/exceptions.h"

#include <gtest/gtest.h>

namespace slipfit {
namespace {

/// Fraction of points whose neighborhood is classified as \a type.
double fraction(const testing::Cloud& c, int k, SlippageType type) {
  auto cloud = std::make_shared<testing::Cloud>(c);
  const auto hoods = testing::knnNeighborhoods(cloud, k);
  LocalSlippage<pcl::PointNormal> local;
  local.setInputCloud(cloud);
  local.setNeighborhoods(hoods);
  pcl::PointCloud<PointSlippage> out;
  local.compute(out);
  EXPECT_EQ(out.size(), cloud->size());
  std::size_t hit = 0;
  for (const auto& p : out)
    hit += p.slippage_type == static_cast<int>(type) ? 1 : 0;
  return static_cast<double>(hit) / static_cast<double>(out.size());
}

TEST(LocalSlippage, PlanesAndCylindersWithModerateNeighborhoods) {
  EXPECT_GT(fraction(testing::samplePlane(5000, -1, 1, -1, 1, 0.5f, 1), 30, SlippageType::plane),
            0.99);
  // A thin cylinder: the neighborhoods (k = 60) span a good part of the circumference.
  const double f = fraction(testing::sampleCylinder(8000, Eigen::Vector3f::Zero(), 0.1f, 2.0f, 2),
                            60, SlippageType::cylinder);
  std::cout << "cylinder points classified as cylinder: " << f << "\n";
  EXPECT_EQ(f, 1.0);  // docs/THEORY.md §5: 100 %
}

TEST(LocalSlippage, NeedsNeighborhoods) {
  LocalSlippage<pcl::PointNormal> local;
  local.setInputCloud(
      std::make_shared<testing::Cloud>(testing::samplePlane(100, 0, 1, 0, 1, 0, 3)));
  pcl::PointCloud<PointSlippage> out;
  EXPECT_THROW(local.compute(out), DegenerateInputError);
}

// setIndices (PCL's contract): the output is index-aligned with the indices, and each point's
// result is the whole cloud's at that point (its neighborhood is the cloud's either way).
TEST(LocalSlippage, IndicesGiveTheirPointsResultsInTheirOrder) {
  auto cloud = std::make_shared<testing::Cloud>(
      testing::sampleCylinder(3000, Eigen::Vector3f::Zero(), 0.2f, 1.0f, 4));
  const auto hoods = testing::knnNeighborhoods(cloud, 30);
  LocalSlippage<pcl::PointNormal> local;
  local.setInputCloud(cloud);
  local.setNeighborhoods(hoods);
  pcl::PointCloud<PointSlippage> whole, part;
  local.compute(whole);
  auto indices = std::make_shared<pcl::Indices>();
  for (pcl::index_t i = 2999; i >= 0; i -= 7)  // descending: the order is the indices'
    indices->push_back(i);
  local.setIndices(indices);
  local.compute(part);
  ASSERT_EQ(part.size(), indices->size());
  for (std::size_t j = 0; j < indices->size(); ++j) {
    const PointSlippage& a = part[j];
    const PointSlippage& b = whole[static_cast<std::size_t>((*indices)[j])];
    ASSERT_EQ(a.slippage_type, b.slippage_type) << j;
    ASSERT_EQ(a.motions, b.motions) << j;
    ASSERT_EQ(a.axis_x, b.axis_x) << j;
    ASSERT_EQ(a.gap, b.gap) << j;
  }
}

}  // namespace
}  // namespace slipfit
