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

}  // namespace
}  // namespace slipfit
