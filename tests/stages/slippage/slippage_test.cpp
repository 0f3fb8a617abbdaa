#include "slipfit/slippage/slippage.h"
#include "slipfit/core/angle_units.h"

#include "expect_refused.h"
#include "slipfit/core/exceptions.h"
#include "slipfit/sampling/motion_surface_sampler.h"
#include "slipfit/sampling/primitive_sampler.h"
#include "slipfit/sampling/torus_sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

namespace slipfit {
namespace {

TEST(SlippageOptions, ValidateNamesTheFieldOutOfItsRange) {
  using testing::expectRefused;
  expectRefused<SlippageOptions>("threshold", [](auto& o) { o.threshold = 1.0; });
  expectRefused<SlippageOptions>("profile_tolerance", [](auto& o) { o.profile_tolerance = 0.0; });
  expectRefused<SlippageOptions>("pitch_tolerance", [](auto& o) { o.pitch_tolerance = -1e-3; });
  expectRefused<SlippageOptions>("noise_floor", [](auto& o) { o.noise_floor = std::nan(""); });
  expectRefused<SlippageOptions>("flat_radius", [](auto& o) { o.flat_radius = 0.5; });
  SlippageOptions o;
  // The entry points check them.
  o.threshold = 0.0;
  const Eigen::Matrix3Xd p = Eigen::Matrix3Xd::Random(3, 20), n = Eigen::Matrix3Xd::Random(3, 20);
  EXPECT_THROW(analyzeSlippage(p, n, Eigen::VectorXd::Ones(20), o), InvalidParameterError);
}

struct Cloud3 {
  Eigen::Matrix3Xd x, n;
};

Cloud3 primitiveCloud(const Primitive& shape, double noise, std::uint64_t seed,
                      double flips = 0.0) {
  PrimitiveSamplingParameters p;
  p.primitive = shape;
  p.points = 3000;
  p.noise = noise;
  p.seed = seed;
  p.flip_fraction = flips;
  p.extent = 1.0;
  p.extent_min = std::holds_alternative<Cone>(shape) ? 0.3 : 0.0;
  Cloud3 c;
  samplePrimitive(p, c.x, c.n);
  return c;
}

SlippageResult analyze(const Cloud3& c) {
  return analyzeSlippage(c.x, c.n, Eigen::VectorXd::Ones(c.x.cols()));
}

double lineAngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized())))) / kDegree;
}

TEST(Slippage, MotionCountsAndTypesOfThePrimitives) {
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  const Eigen::Vector3d where(3, -2, 7);
  struct Case {
    Primitive shape;
    SlippageType type;
    int motions;
  };
  const Case cases[] = {{Plane{axis, 2.0}, SlippageType::plane, 3},
                        {Sphere{where, 0.7}, SlippageType::sphere, 3},
                        {Cylinder{axis, where, 0.4}, SlippageType::cylinder, 2},
                        {Cone{axis, where, 30 * kDegree}, SlippageType::cone, 1}};
  for (const auto& c : cases) {
    for (const double flips : {0.0, 0.5}) {
      const SlippageResult r = analyze(primitiveCloud(c.shape, 0.0, 7, flips));
      EXPECT_EQ(r.type, c.type) << slippageTypeName(c.type) << " got " << slippageTypeName(r.type)
                                << " " << r.reason;
      EXPECT_EQ(r.motions, c.motions) << slippageTypeName(c.type);
      ASSERT_TRUE(r.primitive) << slippageTypeName(c.type);
    }
  }
}

TEST(Slippage, RecoversAxesCentresAndApexAtOnePercentNoise) {
  const Eigen::Vector3d axis = Eigen::Vector3d(-0.2, 0.9, 0.4).normalized();
  const Eigen::Vector3d where(-1, 4, 2);
  SlippageResult r = analyze(primitiveCloud(Cylinder{axis, where, 0.5}, 0.005, 3));
  ASSERT_EQ(r.type, SlippageType::cylinder);
  EXPECT_LT(lineAngleDeg(*r.axis, axis), 1.0);
  const Eigen::Vector3d off = *r.point - where;
  EXPECT_LT((off - off.dot(axis) * axis).norm(), 0.01);

  r = analyze(primitiveCloud(Sphere{where, 0.8}, 0.008, 4));
  ASSERT_EQ(r.type, SlippageType::sphere);
  EXPECT_LT((*r.center - where).norm(), 0.01);

  r = analyze(primitiveCloud(Plane{axis, 1.0}, 0.01, 5));
  ASSERT_EQ(r.type, SlippageType::plane);
  EXPECT_LT(lineAngleDeg(*r.normal, axis), 1.0);

  r = analyze(primitiveCloud(Cone{axis, where, 25 * kDegree}, 0.01, 6));
  ASSERT_EQ(r.type, SlippageType::cone) << slippageTypeName(r.type);
  EXPECT_LT(lineAngleDeg(*r.axis, axis), 1.0);
  EXPECT_GT(r.axis->dot(axis), 0.0) << "the cone axis points into the opening";
  EXPECT_LT((*r.point - where).norm(), 0.05);
  EXPECT_NEAR(std::get<Cone>(*r.primitive).half_angle / kDegree, 25.0, 1.0);
}

TEST(Slippage, TorusIsASurfaceOfRevolutionWithACircularProfile) {
  TorusSamplingParameters p;
  p.shape = {1.0, 0.3};
  p.axis = Eigen::Vector3d(1, 1, 0);
  p.center = Eigen::Vector3d(2, 0, -1);
  p.points = 5000;
  TorusSampler s;
  s.setParameters(p);
  Eigen::Matrix3Xd x, n;
  s.sample(x, n);
  const SlippageResult r = analyzeSlippage(x, n, Eigen::VectorXd::Ones(x.cols()));
  EXPECT_EQ(r.type, SlippageType::torus) << slippageTypeName(r.type);
  EXPECT_EQ(r.motions, 1);
  EXPECT_LT(lineAngleDeg(*r.axis, p.axis), 1e-6);
}

TEST(Slippage, ExtrusionAndHelix) {
  // An extruded ellipse (one translation) and a helicoid (one screw motion).
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0, 1);
  Eigen::Matrix3Xd x(3, 3000), n(3, 3000);
  for (int i = 0; i < 3000; ++i) {
    const double t = 2 * kPi * u(rng), z = 2 * u(rng);
    x.col(i) = Eigen::Vector3d(1.0 * std::cos(t), 0.4 * std::sin(t), z);
    n.col(i) = Eigen::Vector3d(0.4 * std::cos(t), 1.0 * std::sin(t), 0).normalized();
  }
  SlippageResult r = analyzeSlippage(x, n, Eigen::VectorXd::Ones(3000));
  EXPECT_EQ(r.type, SlippageType::extrusion) << slippageTypeName(r.type);
  EXPECT_LT(lineAngleDeg(*r.axis, Eigen::Vector3d::UnitZ()), 1e-6);

  const double h = 0.3;  // rise per radian
  for (int i = 0; i < 3000; ++i) {
    const double t = 4 * kPi * u(rng), rad = 0.2 + 0.8 * u(rng);
    x.col(i) = Eigen::Vector3d(rad * std::cos(t), rad * std::sin(t), h * t);
    n.col(i) = Eigen::Vector3d(h * std::sin(t), -h * std::cos(t), rad).normalized();
  }
  r = analyzeSlippage(x, n, Eigen::VectorXd::Ones(3000));
  EXPECT_EQ(r.type, SlippageType::helix) << slippageTypeName(r.type);
  ASSERT_TRUE(r.pitch);
  EXPECT_NEAR(std::abs(*r.pitch), h, 1e-6);
}

TEST(Slippage, OneMotionSamplersAreClassifiedAsSuch) {
  for (const auto& [surface, name] : kMotionSurfaceNames) {
    for (const double noise : {0.0, 0.005}) {
      MotionSurfaceParameters p;
      p.surface = surface;
      p.noise = noise;
      Eigen::Matrix3Xd x, n;
      sampleMotionSurface(p, x, n);
      const SlippageResult r = analyzeSlippage(x, n, Eigen::VectorXd::Ones(x.cols()));
      const bool extrusion =
          surface == MotionSurface::extrusion || surface == MotionSurface::open_extrusion;
      const SlippageType expected = surface == MotionSurface::revolution ? SlippageType::revolution
                                    : extrusion                          ? SlippageType::extrusion
                                                                         : SlippageType::helix;
      EXPECT_EQ(r.type, expected) << name << " noise " << noise << ": got "
                                  << slippageTypeName(r.type);
      EXPECT_EQ(r.motions, 1) << name;
      ASSERT_TRUE(r.axis) << name;
      EXPECT_LT(lineAngleDeg(*r.axis, Eigen::Vector3d::UnitZ()), 1.0) << name;
      if (expected == SlippageType::helix)
        EXPECT_NEAR(std::abs(*r.pitch), p.pitch, 0.01 * p.pitch);
    }
  }
}

TEST(Slippage, DegenerateInput) {
  Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Random(3, 5), n = Eigen::Matrix3Xd::Random(3, 5);
  EXPECT_EQ(analyzeSlippage(x, n, Eigen::VectorXd::Ones(5)).type, SlippageType::degenerate);
  Eigen::Matrix3Xd line(3, 50), ln(3, 50);
  for (int i = 0; i < 50; ++i) {
    line.col(i) = Eigen::Vector3d(i, 0, 0);
    ln.col(i) = Eigen::Vector3d(0, 0, 1);
  }
  const SlippageResult r = analyzeSlippage(line, ln, Eigen::VectorXd::Ones(50));
  EXPECT_EQ(r.type, SlippageType::degenerate);
  EXPECT_GE(r.motions, 4);
  n.col(2).setZero();
  x = Eigen::Matrix3Xd::Random(3, 5);
}

}  // namespace
}  // namespace slipfit
