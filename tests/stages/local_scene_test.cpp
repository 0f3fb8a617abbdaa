// Per-point slippage on a scene of a plane, a cylinder and a sphere (exact normals): the fraction
// of right types away from the boundaries between the objects.
#include "slipfit/local_slippage.h"

#include "shapes.h"
#include "slipfit/neighborhood_selection.h"

#include <gtest/gtest.h>

#include <iostream>
#include <map>

namespace slipfit {
namespace {

TEST(LocalSlippageScene, TypesAwayFromTheBoundaries) {
  using testing::Cloud;
  // Curvature radii comparable to the neighborhoods (k = 60 spans ~0.1 here).
  auto cloud = std::make_shared<Cloud>(testing::samplePlane(30000, -2, 2, -2, 2, 0, 1));
  const std::size_t plane_end = cloud->size();
  testing::append(*cloud, testing::sampleCylinder(12000, Eigen::Vector3f(1, 1, 0), 0.15f, 1.0f, 2));
  const std::size_t cylinder_end = cloud->size();
  testing::append(*cloud, testing::sampleSphere(8000, Eigen::Vector3f(-1, -1, 1), 0.2f, 3));

  NeighborhoodSelection<pcl::PointNormal> s;
  NeighborhoodParameters np;
  np.k = 60;
  s.setParameters(np);
  s.setInputCloud(cloud);
  auto hoods = std::make_shared<Neighborhoods>();
  s.compute(*hoods);
  LocalSlippage<pcl::PointNormal> local;
  local.setInputCloud(cloud);
  local.setNeighborhoods(hoods);
  pcl::PointCloud<PointSlippage> out;
  local.compute(out);

  // "Away from the boundaries": plane points farther than 0.3 from the cylinder's foot, cylinder
  // points above z = 0.2.
  std::size_t right[3] = {0, 0, 0}, total[3] = {0, 0, 0};
  std::map<int, std::size_t> sphere_types;
  for (std::size_t i = 0; i < cloud->size(); ++i) {
    const Eigen::Vector3f p = (*cloud)[i].getVector3fMap();
    int object = i < plane_end ? 0 : i < cylinder_end ? 1 : 2;
    if (object == 0 && (p.head<2>() - Eigen::Vector2f(1, 1)).norm() < 0.3f)
      continue;
    if (object == 1 && p.z() < 0.2f)
      continue;
    const SlippageType want = object == 0   ? SlippageType::plane
                              : object == 1 ? SlippageType::cylinder
                                            : SlippageType::sphere;
    ++total[object];
    if (object == 2)
      ++sphere_types[out[i].slippage_type];
    right[object] += out[i].slippage_type == static_cast<int>(want) ? 1 : 0;
  }
  std::cout << "sphere points by type:";
  for (const auto& [t, c] : sphere_types)
    std::cout << " " << slippageTypeName(static_cast<SlippageType>(t)) << " " << c;
  std::cout << "\n";
  const char* names[] = {"plane", "cylinder", "sphere"};
  for (int o = 0; o < 3; ++o) {
    const double f = static_cast<double>(right[o]) / static_cast<double>(total[o]);
    std::cout << names[o] << ": " << right[o] << "/" << total[o] << " = " << f << " right\n";
    EXPECT_GT(f, 0.9) << names[o];
  }
}

}  // namespace
}  // namespace slipfit
