// Estimates consistently oriented normals of a small sphere with slipfit's PCL-style classes and
// checks that they point outward.
#include <slipfit/neighborhoods/neighborhood_selection.h>
#include <slipfit/neighborhoods/normal_estimation.h>

#include <pcl/point_types.h>

#include <cmath>
#include <iostream>

int main() {
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  const int rings = 40, segments = 80;
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double t = M_PI * i / rings, p = 2 * M_PI * j / segments;
      cloud->push_back(
          pcl::PointXYZ(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)));
    }
  auto hoods = std::make_shared<slipfit::Neighborhoods>();
  slipfit::NeighborhoodSelection<pcl::PointXYZ> selection;
  selection.setInputCloud(cloud);
  selection.compute(*hoods);

  slipfit::OrientedNormalEstimation<pcl::PointXYZ, pcl::Normal> estimation;
  slipfit::NormalParameters parameters;
  parameters.orientation = slipfit::NormalOrientation::consistent;
  estimation.setParameters(parameters);
  estimation.setInputCloud(cloud);
  estimation.setNeighborhoods(hoods);
  pcl::PointCloud<pcl::Normal> normals;
  estimation.compute(normals);
  for (std::size_t i = 0; i < cloud->size(); ++i)
    if ((*cloud)[i].getVector3fMap().dot(normals[i].getNormalVector3fMap()) <= 0) {
      std::cerr << "inward normal at " << i << "\n";
      return 1;
    }
  std::cout << "consumer: " << normals.size() << " outward normals\n";
  return 0;
}
