#pragma once
/// \file PCL's cylinder tutorial (cylinder_segmentation.cpp) as it ships, the oracle for a
/// tabletop frame's mug: z cropped to [0, 1.5], normals of 50 neighbours, the table removed by a
/// NORMAL_PLANE RANSAC (normal weight 0.1, 100 iterations, 3 cm), then a CYLINDER RANSAC on the
/// rest (weight 0.1, 10,000 iterations, 5 cm, radius 0–0.1 m). PCL's default generator: the same
/// cylinder on every run.

#include <pcl/features/normal_3d.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/sac_segmentation.h>
#include <Eigen/Core>

#include <vector>

namespace slipfit::testing {

struct TutorialCylinder {
  Eigen::Vector3d point = Eigen::Vector3d::Zero(), axis = Eigen::Vector3d::Zero();  ///< unit axis
  double radius = 0.0;  ///< 0 when RANSAC found none
  /// The cropped points (indices into the input) and their normals, k = 50, facing the origin.
  std::vector<int> cropped;
  pcl::PointCloud<pcl::Normal> normals;
  std::vector<int> inliers;  ///< the cylinder's inliers, indices into the input
};

template <typename PointT>
TutorialCylinder tutorialCylinder(const pcl::PointCloud<PointT>& input) {
  TutorialCylinder out;
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  for (std::size_t i = 0; i < input.size(); ++i)
    if (input[i].z >= 0.0f && input[i].z <= 1.5f) {
      cloud->push_back(pcl::PointXYZ(input[i].x, input[i].y, input[i].z));
      out.cropped.push_back(static_cast<int>(i));
    }
  auto normals = pcl::make_shared<pcl::PointCloud<pcl::Normal>>();
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> estimation;
  estimation.setSearchMethod(pcl::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
  estimation.setInputCloud(cloud);
  estimation.setKSearch(50);
  estimation.compute(*normals);
  out.normals = *normals;

  pcl::SACSegmentationFromNormals<pcl::PointXYZ, pcl::Normal> sac;
  sac.setOptimizeCoefficients(true);
  sac.setModelType(pcl::SACMODEL_NORMAL_PLANE);
  sac.setNormalDistanceWeight(0.1);
  sac.setMethodType(pcl::SAC_RANSAC);
  sac.setMaxIterations(100);
  sac.setDistanceThreshold(0.03);
  sac.setInputCloud(cloud);
  sac.setInputNormals(normals);
  pcl::PointIndices table;
  pcl::ModelCoefficients plane;
  sac.segment(table, plane);
  std::vector<char> in_table(cloud->size(), 0);
  for (const auto i : table.indices)
    in_table[static_cast<std::size_t>(i)] = 1;
  auto rest = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  auto rest_normals = pcl::make_shared<pcl::PointCloud<pcl::Normal>>();
  std::vector<int> rest_to_input;
  for (std::size_t i = 0; i < cloud->size(); ++i)
    if (!in_table[i]) {
      rest->push_back((*cloud)[i]);
      rest_normals->push_back((*normals)[i]);
      rest_to_input.push_back(out.cropped[i]);
    }

  sac.setModelType(pcl::SACMODEL_CYLINDER);
  sac.setMaxIterations(10000);
  sac.setDistanceThreshold(0.05);
  sac.setRadiusLimits(0, 0.1);
  sac.setInputCloud(rest);
  sac.setInputNormals(rest_normals);
  pcl::PointIndices inliers;
  pcl::ModelCoefficients cylinder;
  sac.segment(inliers, cylinder);
  if (cylinder.values.size() != 7)
    return out;
  out.point = Eigen::Vector3d(cylinder.values[0], cylinder.values[1], cylinder.values[2]);
  out.axis =
      Eigen::Vector3d(cylinder.values[3], cylinder.values[4], cylinder.values[5]).normalized();
  out.radius = cylinder.values[6];
  for (const auto i : inliers.indices)
    out.inliers.push_back(rest_to_input[static_cast<std::size_t>(i)]);
  return out;
}

}  // namespace slipfit::testing
