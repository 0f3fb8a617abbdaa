// Depth recorded on levels (Kinect-like: step c·z²) is detected, with its local step; flat CAD
// faces and continuous noise are not; neighborhoods widened across the levels give the surface's
// normal where the k nearest of one level give the view axis.

#include "kinect_plane.h"
#include "shared_neighborhoods.h"

#include "slipfit/neighborhoods/depth_quantization.h"
#include "slipfit/neighborhoods/neighborhood_selection.h"
#include "slipfit/sampling/random_vector.h"

#include <gtest/gtest.h>
#include <pcl/point_types.h>
#include <Eigen/Geometry>

#include <cmath>
#include <iostream>
#include <random>

namespace slipfit {
namespace {

using testing::kinectPlane;
using testing::kStepPerZ2;

TEST(DepthQuantization, KinectLikeDepthIsDetectedWithItsLocalStep) {
  const Eigen::Matrix3Xd p = kinectPlane(0.001, true, 1);
  const QuantizedAxis q = detectQuantizedAxis(p);
  ASSERT_TRUE(q.detected());
  EXPECT_EQ(q.axis, 2);
  // Levels 1/(c d) lie c z²/(1 ± c z) apart: the local step is c·z² to within 1 %.
  for (double z : {1.3, 1.5, 1.8}) {
    const double expected = kStepPerZ2 * z * z;
    EXPECT_NEAR(q.stepAt(Eigen::Vector3d(0, 0, z)), expected, 0.01 * expected) << "z " << z;
  }
}

TEST(DepthQuantization, ContinuousNoiseFewFlatFacesAndGridsAreNotALattice) {
  EXPECT_FALSE(detectQuantizedAxis(kinectPlane(0.001, false, 2)).detected());
  // A CAD-like plate: two faces at z = 0 and z = 1 (all points on two levels) and rounded x, y.
  Eigen::Matrix3Xd plate(3, 20000);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (Eigen::Index i = 0; i < plate.cols(); ++i)
    plate.col(i) << randomVector<2>(u, rng), static_cast<double>(i % 2);
  EXPECT_FALSE(detectQuantizedAxis(plate).detected());
  // A regular grid: x and y on 100 levels each, z continuous — a grid sampling, not depth levels.
  Eigen::Matrix3Xd grid(3, 10000);
  for (Eigen::Index i = 0; i < grid.cols(); ++i)
    grid.col(i) = Eigen::Vector3d(0.01 * static_cast<double>(i % 100),
                                  0.01 * static_cast<double>(i / 100), u(rng));
  EXPECT_FALSE(detectQuantizedAxis(grid).detected());
}

// The same depth frame registered into another frame — turned 30°, 20° and 10° about x, y and z,
// moved, and stored as floats, as a registered frame is: no coordinate axis holds a lattice, and
// the levels are found across the camera's axis, with their steps. The direction is asserted
// within 1e-7 rad of the camera's axis (measured 3.0e-8). A continuous plane and a CAD-like
// plate, turned alike, hold none.
TEST(DepthQuantization, ARegisteredFramesLevelsAreFoundAcrossTheCamerasAxis) {
  const Eigen::Matrix3d turn = (Eigen::AngleAxisd(30.0 * M_PI / 180.0, Eigen::Vector3d::UnitX()) *
                                Eigen::AngleAxisd(20.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()) *
                                Eigen::AngleAxisd(10.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ()))
                                   .toRotationMatrix();
  const Eigen::Vector3d shift(0.3, -0.2, 1.1);
  const auto registered = [&](const Eigen::Matrix3Xd& p) -> Eigen::Matrix3Xd {
    return ((turn * p).colwise() + shift).cast<float>().cast<double>();
  };
  const QuantizedAxis q = detectQuantizedAxis(registered(kinectPlane(0.001, true, 1)));
  ASSERT_TRUE(q.detected());
  EXPECT_EQ(q.axis, QuantizedAxis::kAlongDirection);
  const double off = std::acos(std::min(1.0, std::abs(q.direction.dot(turn.col(2)))));
  std::cout << "registered frame: levels across a direction " << off << " rad off the camera's\n";
  EXPECT_LT(off, 1e-7);
  for (double z : {1.3, 1.5, 1.8}) {
    const double expected = kStepPerZ2 * z * z;
    EXPECT_NEAR(q.stepAt(Eigen::Vector3d(turn * Eigen::Vector3d(0, 0, z) + shift)), expected,
                0.01 * expected)
        << "z " << z;
  }
  EXPECT_FALSE(detectQuantizedAxis(registered(kinectPlane(0.001, false, 2))).detected());
  Eigen::Matrix3Xd plate(3, 20000);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (Eigen::Index i = 0; i < plate.cols(); ++i)
    plate.col(i) << randomVector<2>(u, rng), static_cast<double>(i % 2);
  EXPECT_FALSE(detectQuantizedAxis(registered(plate)).detected());
}

TEST(DepthQuantization, WidenedNeighborhoodsSeeTheSurfaceNotTheSlice) {
  // With the sensor's noise (1 mm) before the rounding, as on real scans: noise-free levels of a
  // pixel grid also put x and y on lattices, which reads as a grid sampling (not detected).
  const Eigen::Matrix3Xd p = kinectPlane(0.001, true, 4);
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  for (Eigen::Index i = 0; i < p.cols(); ++i) {
    pcl::PointNormal q;
    q.x = static_cast<float>(p(0, i));
    q.y = static_cast<float>(p(1, i));
    q.z = static_cast<float>(p(2, i));
    cloud->push_back(q);
  }
  const double tilt = 40.0 * M_PI / 180.0;
  const Eigen::Vector3d truth(0.0, -std::sin(tilt), std::cos(tilt));  // ⟂ to (0, cos, sin)
  auto meanError = [&](bool span) {
    NeighborhoodSelection<pcl::PointNormal> selection;
    NeighborhoodParameters parameters;
    parameters.k = 12;
    parameters.span_quantization = span;
    selection.setParameters(parameters);
    selection.setInputCloud(cloud);
    auto hoods = std::make_shared<Neighborhoods>();
    selection.compute(*hoods);
    auto copy = pcl::make_shared<pcl::PointCloud<pcl::PointNormal>>(*cloud);
    testing::estimateNormals(copy, hoods);
    double sum = 0.0;
    for (const auto& q : *copy)
      sum += std::acos(std::min(1.0, std::abs(q.getNormalVector3fMap().cast<double>().dot(truth))));
    return sum / static_cast<double>(copy->size()) * 180.0 / M_PI;
  };
  // Within one level the k nearest are flat in z: their normal is the view axis, 40° off
  // (measured mean 31°: some neighborhoods straddle two levels).
  const double narrow = meanError(false), wide = meanError(true);
  std::cout << "mean normal error: " << narrow << "° in the k nearest, " << wide << "° widened\n";
  EXPECT_GT(narrow, 25.0);
  // Spanning 1.5 steps they see the plane: the residual tilt is what quantization leaves,
  // a step over the neighborhood's width (1.5 steps each side): atan(1/3) ≈ 18° at worst,
  // far less on average (measured 5.4° with the 1 mm noise).
  EXPECT_LT(wide, 6.0);
}

}  // namespace
}  // namespace slipfit
