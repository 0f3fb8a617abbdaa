// PrimitiveFitting as a PCL user meets it: PCL clouds in, PCL coefficients out, and PCL's own
// cylinder-segmentation tutorial flow with slipfit's classes swapped in.
#include "slipfit/fitting/primitive_fitting.h"
#include "slipfit/core/angle_units.h"

#include "shapes.h"
#include "slipfit/core/exceptions.h"
#include "slipfit/neighborhoods/normal_estimation.h"
#include "slipfit/sampling/primitive_sampler.h"

#include <gtest/gtest.h>

#include <pcl/filters/extract_indices.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/sample_consensus/sac_model_cone.h>
#include <pcl/sample_consensus/sac_model_cylinder.h>
#include <pcl/sample_consensus/sac_model_plane.h>
#include <pcl/sample_consensus/sac_model_sphere.h>
#include <pcl/segmentation/sac_segmentation.h>

namespace slipfit {
namespace {

using Cloud = pcl::PointCloud<pcl::PointNormal>;

Cloud::Ptr cloudOf(const Primitive& shape, std::size_t n, double noise = 0.0) {
  PrimitiveSamplingParameters p;
  p.primitive = shape;
  p.points = n;
  p.noise = noise;
  p.extent = 1.0;
  p.extent_min = std::holds_alternative<Cone>(shape) ? 0.3 : 0.0;
  Eigen::Matrix3Xd x, nn;
  samplePrimitive(p, x, nn);
  auto c = std::make_shared<Cloud>();
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    pcl::PointNormal q;
    q.getVector3fMap() = x.col(i).cast<float>();
    q.getNormalVector3fMap() = nn.col(i).cast<float>();
    c->push_back(q);
  }
  return c;
}

template <typename Model>
double maxPclDistance(const Cloud::Ptr& cloud, const pcl::ModelCoefficients& c) {
  typename Model::Ptr model(new Model(cloud));
  if constexpr (std::is_base_of_v<
                    pcl::SampleConsensusModelFromNormals<pcl::PointNormal, pcl::PointNormal>,
                    Model>) {
    model->setInputNormals(cloud);
    model->setNormalDistanceWeight(0.0);
  }
  Eigen::VectorXf coefficients = Eigen::Map<const Eigen::VectorXf>(
      c.values.data(), static_cast<Eigen::Index>(c.values.size()));
  std::vector<double> distances;
  model->getDistancesToModel(coefficients, distances);
  return *std::max_element(distances.begin(), distances.end());
}

TEST(PrimitiveFitting, CoefficientsMeanTheSameToPclsSacModels) {
  const Primitive shapes[] = {
      Plane{Eigen::Vector3d(1, 2, 2) / 3.0, 0.7}, Sphere{Eigen::Vector3d(0.5, -1, 2), 0.8},
      Cylinder{Eigen::Vector3d(0, 1, 1).normalized(), Eigen::Vector3d(1, 0, 0), 0.4},
      Cone{Eigen::Vector3d(1, 0, 1).normalized(), Eigen::Vector3d(0, 1, 0), 20 * kDegree}};
  for (const auto& shape : shapes) {
    const auto cloud = cloudOf(shape, 2000);
    PrimitiveFitting<pcl::PointNormal> fitting;
    fitting.setInputCloud(cloud);
    fitting.setInputNormals(cloud);
    fitting.setType(typeOf(shape));
    const FitResult r = fitting.fit();
    const pcl::ModelCoefficients c = toModelCoefficients(r.refined);
    double d = 0.0;
    switch (typeOf(shape)) {
      case PrimitiveType::plane:
        d = maxPclDistance<pcl::SampleConsensusModelPlane<pcl::PointNormal>>(cloud, c);
        break;
      case PrimitiveType::sphere:
        d = maxPclDistance<pcl::SampleConsensusModelSphere<pcl::PointNormal>>(cloud, c);
        break;
      case PrimitiveType::cylinder:
        d = maxPclDistance<pcl::SampleConsensusModelCylinder<pcl::PointNormal, pcl::PointNormal>>(
            cloud, c);
        break;
      case PrimitiveType::cone:
        d = maxPclDistance<pcl::SampleConsensusModelCone<pcl::PointNormal, pcl::PointNormal>>(cloud,
                                                                                              c);
        break;
      case PrimitiveType::torus:  // PCL 1.13 has no torus model; the shapes above hold none
        ADD_FAILURE() << "no PCL model to read a torus with";
        break;
    }
    EXPECT_LT(d, 1e-4) << primitiveTypeName(typeOf(shape))
                       << ": PCL reads the coefficients differently";
  }
}

TEST(PrimitiveFitting, IndicesWeightsAndErrors) {
  auto cloud = cloudOf(Sphere{Eigen::Vector3d(0, 0, 0), 1.0}, 1000);
  const auto plane = cloudOf(Plane{Eigen::Vector3d(0, 0, 1), 5.0}, 1000);
  *cloud += *plane;
  auto indices = std::make_shared<pcl::Indices>();
  for (int i = 0; i < 1000; ++i)
    indices->push_back(i);
  PrimitiveFitting<pcl::PointNormal> fitting;
  fitting.setInputCloud(cloud);
  fitting.setInputNormals(cloud);
  fitting.setIndices(indices);
  FitResult r = fitting.fit();  // auto
  EXPECT_EQ(r.type, PrimitiveType::sphere);
  EXPECT_NEAR(std::get<Sphere>(r.refined).radius, 1.0, 1e-5);
  // The same selection by weights instead of indices.
  auto weights = std::make_shared<std::vector<float>>(cloud->size(), 0.0f);
  std::fill(weights->begin() + 1000, weights->end(), 1.0f);
  PrimitiveFitting<pcl::PointNormal> by_weight;
  by_weight.setInputCloud(cloud);
  by_weight.setInputNormals(cloud);
  by_weight.setWeights(weights);
  r = by_weight.fit();
  EXPECT_EQ(r.type, PrimitiveType::plane);
  EXPECT_NEAR(std::get<Plane>(r.refined).d * std::get<Plane>(r.refined).normal.z(), 5.0, 1e-5);

  by_weight.setWeights(std::make_shared<std::vector<float>>(cloud->size(), 0.0f));
  EXPECT_THROW(by_weight.fit(), DegenerateInputError);
  PrimitiveFitting<pcl::PointNormal> no_normals;
  no_normals.setInputCloud(cloud);
  no_normals.setType(PrimitiveType::cone);
  EXPECT_THROW(no_normals.fit(), InvalidParameterError);
}

// PCL's "cylinder model segmentation" tutorial: estimate normals, remove the table plane with
// SACSegmentationFromNormals, extract the rest, find the cylinder. slipfit's
// OrientedNormalEstimation and PrimitiveFitting take the place of PCL's, everything else is PCL.
TEST(PrimitiveFitting, PclCylinderTutorialFlowWithSlipfitClasses) {
  auto scene = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  for (const auto& p : testing::samplePlane(20000, -1, 1, -1, 1, 0, 1))
    scene->push_back(pcl::PointXYZ(p.x, p.y, p.z));
  for (const auto& p :
       testing::sampleCylinder(8000, Eigen::Vector3f(0.2f, 0.1f, 0.05f), 0.15f, 0.6f, 2))
    scene->push_back(pcl::PointXYZ(p.x, p.y, p.z));
  auto noisy = std::make_shared<testing::Cloud>();
  for (const auto& p : *scene) {
    pcl::PointNormal q;
    q.getVector3fMap() = p.getVector3fMap();
    noisy->push_back(q);
  }
  testing::addNoise(*noisy, 0.001f, 3);
  for (std::size_t i = 0; i < scene->size(); ++i)
    (*scene)[i].getVector3fMap() = (*noisy)[i].getVector3fMap();

  // Normals: slipfit instead of pcl::NormalEstimation.
  auto normals = std::make_shared<pcl::PointCloud<pcl::Normal>>();
  OrientedNormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
  NormalParameters np;
  np.k = 50;
  ne.setParameters(np);
  ne.setInputCloud(scene);
  ne.compute(*normals);

  // The plane, as in the tutorial.
  pcl::SACSegmentationFromNormals<pcl::PointXYZ, pcl::Normal> seg;
  auto plane_inliers = std::make_shared<pcl::PointIndices>();
  pcl::ModelCoefficients plane_coefficients;
  seg.setOptimizeCoefficients(true);
  seg.setModelType(pcl::SACMODEL_NORMAL_PLANE);
  seg.setNormalDistanceWeight(0.1);
  seg.setMethodType(pcl::SAC_RANSAC);
  seg.setMaxIterations(100);
  seg.setDistanceThreshold(0.01);
  seg.setInputCloud(scene);
  seg.setInputNormals(normals);
  seg.segment(*plane_inliers, plane_coefficients);
  ASSERT_GT(plane_inliers->indices.size(), 15000u);

  pcl::ExtractIndices<pcl::PointXYZ> extract;
  extract.setInputCloud(scene);
  extract.setIndices(plane_inliers);
  extract.setNegative(true);
  auto rest = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  extract.filter(*rest);
  pcl::ExtractIndices<pcl::Normal> extract_normals;
  extract_normals.setInputCloud(normals);
  extract_normals.setIndices(plane_inliers);
  extract_normals.setNegative(true);
  auto rest_normals = std::make_shared<pcl::PointCloud<pcl::Normal>>();
  extract_normals.filter(*rest_normals);

  // The cylinder: slipfit's weighted fit instead of SACMODEL_CYLINDER + RANSAC.
  PrimitiveFitting<pcl::PointXYZ, pcl::Normal> fitting;
  fitting.setInputCloud(rest);
  fitting.setInputNormals(rest_normals);
  fitting.setType(PrimitiveType::cylinder);
  const FitResult r = fitting.fit();
  const auto& cyl = std::get<Cylinder>(r.refined);
  EXPECT_NEAR(cyl.radius, 0.15, 0.0015);
  EXPECT_GT(std::abs(cyl.axis.z()), std::cos(1 * kDegree));
  const pcl::ModelCoefficients c = toModelCoefficients(r.refined);
  ASSERT_EQ(c.values.size(), 7u);  // the layout the tutorial prints
}

}  // namespace
}  // namespace slipfit
