// A PCL application that segments a cloud with slipfit's PCL-style classes, as README.md shows it:
// a floor and a ball, generated, become one plane and one sphere.
#include <slipfit/neighborhoods/neighborhood_selection.h>
#include <slipfit/neighborhoods/normal_estimation.h>
#include <slipfit/segmentation/segmentation.h>
#include <slipfit/slippage/local_slippage.h>

#include <pcl/point_types.h>

#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace {

/// A 2 × 2 floor at z = 0 and a ball of radius 0.4 standing on it, about 0.02 apart.
pcl::PointCloud<pcl::PointNormal>::Ptr floorAndBall() {
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  auto add = [&](double x, double y, double z) {
    pcl::PointNormal p;
    p.x = static_cast<float>(x), p.y = static_cast<float>(y), p.z = static_cast<float>(z);
    cloud->push_back(p);
  };
  for (int i = 0; i <= 100; ++i)
    for (int j = 0; j <= 100; ++j)
      if (std::hypot(i - 50, j - 50) > 21)  // not under the ball
        add(-1.0 + 0.02 * i, -1.0 + 0.02 * j, 0.0);
  // The ball on a Fibonacci spiral (every point at its own height; rings of one height each
  // would read as a depth sensor's levels), but for the cap that touches the floor.
  const int n = 4000;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / n, r = std::sqrt(1.0 - z * z);
    if (z > -0.95)
      add(0.4 * r * std::cos(golden * i), 0.4 * r * std::sin(golden * i), 0.4 + 0.4 * z);
  }
  return cloud;
}

}  // namespace

int main() {
  const pcl::PointCloud<pcl::PointNormal>::Ptr cloud = floorAndBall();

  // The application, in the README's words: neighborhoods, normals, local slippage, segments.
  auto hoods = std::make_shared<slipfit::Neighborhoods>();
  slipfit::NeighborhoodSelection<pcl::PointNormal> selection;
  selection.setInputCloud(cloud);
  selection.compute(*hoods);
  slipfit::OrientedNormalEstimation<pcl::PointNormal, pcl::Normal> estimation;
  estimation.setInputCloud(cloud);
  estimation.setNeighborhoods(hoods);
  pcl::PointCloud<pcl::Normal> normals;
  estimation.compute(normals);
  for (std::size_t i = 0; i < cloud->size(); ++i)
    (*cloud)[i].getNormalVector3fMap() = normals[i].getNormalVector3fMap();
  auto slippage = std::make_shared<pcl::PointCloud<slipfit::PointSlippage>>();
  slipfit::LocalSlippage<pcl::PointNormal> local;
  local.setInputCloud(cloud);
  local.setNeighborhoods(hoods);
  local.compute(*slippage);
  slipfit::SlippageSegmentation<pcl::PointNormal> segmentation;
  segmentation.setInputCloud(cloud);
  segmentation.setNeighborhoods(hoods);
  segmentation.setLocalSlippage(slippage);
  std::vector<pcl::PointIndices> segments;
  segmentation.segment(segments);

  std::vector<std::string> types;
  for (const slipfit::Segment& s : segmentation.result().segments)
    types.emplace_back(slipfit::primitiveTypeName(s.fit.type));
  const bool found = segments.size() == 2 && ((types[0] == "plane" && types[1] == "sphere") ||
                                              (types[0] == "sphere" && types[1] == "plane"));
  std::cout << "consumer: " << cloud->size() << " points, " << segments.size() << " segments:";
  for (std::size_t k = 0; k < segments.size(); ++k)
    std::cout << " " << types[k] << " (" << segments[k].indices.size() << " points)";
  std::cout << "\n";
  if (!found)
    std::cerr << "consumer: expected one plane and one sphere\n";
  return found ? 0 : 1;
}
