// Per-point slippage on a scene of a plane, a cylinder and a sphere: the fraction of right types
// away from the boundaries between the objects, with exact normals and with noisy points and
// normals estimated on the same shared neighborhoods.
#include "slipfit/slippage/local_slippage.h"

#include "shapes.h"
#include "shared_neighborhoods.h"
#include "slipfit/neighborhoods/neighborhood_selection.h"
#include "slipfit/neighborhoods/normal_estimation.h"

#include <gtest/gtest.h>

#include <array>
#include <iostream>
#include <map>

namespace slipfit {
namespace {

/// Fractions of right per-point types (plane, cylinder, sphere) away from the boundaries.
std::array<double, 3> sceneFractions(float noise) {
  using testing::Cloud;
  // Curvature radii comparable to the neighborhoods (k = 60 spans ~0.1 here).
  auto cloud = std::make_shared<Cloud>(testing::samplePlane(30000, -2, 2, -2, 2, 0, 1));
  const std::size_t plane_end = cloud->size();
  testing::append(*cloud, testing::sampleCylinder(12000, Eigen::Vector3f(1, 1, 0), 0.15f, 1.0f, 2));
  const std::size_t cylinder_end = cloud->size();
  testing::append(*cloud, testing::sampleSphere(8000, Eigen::Vector3f(-1, -1, 1), 0.2f, 3));
  const Cloud exact = *cloud;  // "away from the boundaries" is judged on the true positions
  if (noise > 0.0f)
    testing::addNoise(*cloud, noise, 4);

  const auto hoods = testing::knnNeighborhoods(cloud, 60);
  if (noise > 0.0f)
    testing::estimateNormals(cloud, hoods);
  LocalSlippage<pcl::PointNormal> local;
  local.setInputCloud(cloud);
  local.setNeighborhoods(hoods);
  pcl::PointCloud<PointSlippage> out;
  local.compute(out);

  // "Away from the boundaries": plane points farther than 0.3 from the cylinder's foot, cylinder
  // points above z = 0.2.
  std::size_t right[3] = {0, 0, 0}, total[3] = {0, 0, 0};
  std::map<int, std::size_t> types[3];
  for (std::size_t i = 0; i < cloud->size(); ++i) {
    const Eigen::Vector3f p = exact[i].getVector3fMap();
    int object = i < plane_end ? 0 : i < cylinder_end ? 1 : 2;
    if (object == 0 && (p.head<2>() - Eigen::Vector2f(1, 1)).norm() < 0.3f)
      continue;
    if (object == 1 && p.z() < 0.2f)
      continue;
    const SlippageType want = object == 0   ? SlippageType::plane
                              : object == 1 ? SlippageType::cylinder
                                            : SlippageType::sphere;
    ++total[object];
    ++types[object][out[i].slippage_type];
    right[object] += out[i].slippage_type == static_cast<int>(want) ? 1 : 0;
  }
  std::array<double, 3> fractions{};
  const char* names[] = {"plane", "cylinder", "sphere"};
  for (int o = 0; o < 3; ++o) {
    fractions[o] = static_cast<double>(right[o]) / static_cast<double>(total[o]);
    std::cout << names[o] << ": " << right[o] << "/" << total[o] << " = " << fractions[o]
              << " right; by type:";
    for (const auto& [t, count] : types[o])
      std::cout << " " << slippageTypeName(static_cast<SlippageType>(t)) << " " << count;
    std::cout << "\n";
  }
  return fractions;
}

// The figures docs/THEORY.md §5 quotes (seeded scene: the counts are exact).
TEST(LocalSlippageScene, TypesAwayFromTheBoundaries) {
  const auto f = sceneFractions(0.0f);
  EXPECT_EQ(f[0], 1.0);                 // plane: 100 %
  EXPECT_EQ(f[1], 1.0);                 // cylinder: 100 %
  EXPECT_GE(f[2], 1.0 - 1.0 / 8000.0);  // sphere: all but 1 of 8,000
}

// 0.0005 is 0.25 % of the sphere's radius and about 1 % of the neighborhood size.
TEST(LocalSlippageScene, TypesWithNoiseAndEstimatedNormals) {
  const auto f = sceneFractions(0.0005f);
  EXPECT_GE(f[0], 1.0 - 2.0 / 29468.0);  // plane: all but 2 of 29,468 (99.99 %)
  EXPECT_GE(f[1], 1.0 - 1.0 / 9631.0);   // cylinder: all but 1 of 9,631 (99.99 %)
  EXPECT_EQ(f[2], 1.0);                  // sphere: 100 %
}

}  // namespace
}  // namespace slipfit
