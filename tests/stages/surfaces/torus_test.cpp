#include "slipfit/surfaces/torus.h"
#include "slipfit/core/angle_units.h"

#include "slipfit/core/exceptions.h"
#include "slipfit/sampling/random_vector.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace slipfit {
namespace {

const TorusShape kTestTorus{3.0, 1.25};

TEST(TorusBezier, SitesOfTheFirstQuarter) {
  const auto s = torusQuarterSites(kTestTorus);
  EXPECT_EQ(s[4], HomogeneousPoint::Zero()) << "the middle site is the zero site";
  EXPECT_EQ(s[0], HomogeneousPoint(1, 4.25, 0, 0));
  EXPECT_EQ(s[1], HomogeneousPoint(0, 0, 4.25, 0));  // at infinity, direction +y
  EXPECT_EQ(s[2], HomogeneousPoint(1, -4.25, 0, 0));
  EXPECT_EQ(s[3], HomogeneousPoint(0, 0, 0, 1.25));  // at infinity, direction +z
  EXPECT_EQ(s[5], HomogeneousPoint(0, 0, 0, 1.25));
  EXPECT_EQ(s[6], HomogeneousPoint(1, 1.75, 0, 0));
  EXPECT_EQ(s[7], HomogeneousPoint(0, 0, 1.75, 0));
  EXPECT_EQ(s[8], HomogeneousPoint(1, -1.75, 0, 0));
}

TEST(TorusBezier, CornersAndCentreAreExact) {
  const RationalBezierPatch q = torusQuarterPatch(kTestTorus, 0);
  EXPECT_EQ(q.evaluate(0, 0).position, Eigen::Vector3d(4.25, 0, 0));
  EXPECT_EQ(q.evaluate(1, 0).position, Eigen::Vector3d(1.75, 0, 0));
  EXPECT_EQ(q.evaluate(0, 1).position, Eigen::Vector3d(-4.25, 0, 0));
  EXPECT_EQ(q.evaluate(1, 1).position, Eigen::Vector3d(-1.75, 0, 0));
  // V(1/2, 1/2): Q = T = 1, α = β = π/2.
  EXPECT_EQ(q.evaluate(0.5, 0.5).position, Eigen::Vector3d(0, 3.0, 1.25));
}

TEST(TorusBezier, RandomPointsSatisfyTheImplicitEquationAndMatchTheAngles) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * kPi);
  for (int i = 0; i < 20000; ++i) {
    const double a = angle(rng), b = angle(rng);
    const SurfacePoint s = evaluateTorusBezier(kTestTorus, a, b);
    ASSERT_LE(std::abs(torusImplicit(kTestTorus, s.position)), 1e-12 * kTestTorus.R * kTestTorus.R)
        << a << " " << b;
    ASSERT_LE((s.position - torusPoint(kTestTorus, a, b)).norm(), 1e-12 * kTestTorus.R);
    ASSERT_LE((s.normal - torusNormal(a, b)).norm(), 1e-12)
        << "outward normal at " << a << " " << b;
  }
}

TEST(TorusBezier, QuarterParametersAndAnglesInvert) {
  for (double u = 0; u <= 1.0; u += 0.125)
    EXPECT_NEAR(quarterParameter(quarterAngle(u), 0).u, u, 1e-15);
  const QuarterParameter q = quarterParameter(1.5 * kPi, 0.25 * kPi);
  EXPECT_EQ(q.quarter, 1);
  EXPECT_NEAR(q.u, 0.5, 1e-15);
}

TEST(TorusNurbs, AgreesWithBezierAndTheImplicitEquation) {
  const NurbsSurface nurbs = torusNurbs(kTestTorus);
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 20000; ++i) {
    // A random Bézier parameter in a random quarter, mapped through the angles to the NURBS one.
    const int quarter = static_cast<int>(rng() % 4);
    const double u = unit(rng), v = unit(rng);
    const Eigen::Vector3d x = torusQuarterPatch(kTestTorus, quarter).evaluate(u, v).position;
    const double a = std::atan2(x.z(), std::hypot(x.x(), x.y()) - kTestTorus.R);
    const double b = std::atan2(x.y(), x.x());
    const Eigen::Vector2d uv = torusNurbsParameter(a, b);
    const SurfacePoint n = nurbs.evaluate(uv.x(), uv.y());
    ASSERT_LE((n.position - x).norm(), 1e-12 * kTestTorus.R) << quarter << " " << u << " " << v;
    ASSERT_LE(std::abs(torusImplicit(kTestTorus, n.position)), 1e-12 * kTestTorus.R * kTestTorus.R);
    // u runs around the tube and v around the axis, like α and β: Su × Sv points inward.
    ASSERT_NEAR(n.normal.dot(torusNormal(a, b)), -1.0, 1e-12);
  }
}

TEST(TorusNurbs, WeightsAreOneRootHalfAndHalf) {
  const NurbsSurface nurbs = torusNurbs(kTestTorus);
  EXPECT_EQ(nurbs.countU(), 9);
  EXPECT_EQ(nurbs.degreeU(), 2);
  EXPECT_EQ(nurbs.knotsV(),
            (std::vector<double>{0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1}));
}

TEST(Nurbs, ClampedWithoutInnerKnotsEqualsTheRationalBezierPatch) {
  // Degrees (3, 2), random points and weights: de Boor and de Casteljau must agree.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> c(-2.0, 2.0), w(0.2, 3.0), unit(0.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  std::vector<HomogeneousPoint> sites;
  for (int k = 0; k < 12; ++k) {
    points.push_back(randomVector<3>(c, rng));
    weights.push_back(w(rng));
    HomogeneousPoint h;
    h << weights.back(), weights.back() * points.back();
    sites.push_back(h);
  }
  const NurbsSurface nurbs(3, 2, {0, 0, 0, 0, 1, 1, 1, 1}, {0, 0, 0, 1, 1, 1}, 4, 3, points,
                           weights);
  const RationalBezierPatch bezier(3, 2, sites);
  for (int i = 0; i < 1000; ++i) {
    const double u = i == 0 ? 1.0 : unit(rng), v = i == 0 ? 1.0 : unit(rng);
    const SurfacePoint a = nurbs.evaluate(u, v), b = bezier.evaluate(u, v);
    ASSERT_LE((a.position - b.position).norm(), 1e-12);
    ASSERT_LE((a.du - b.du).norm(), 1e-11);
    ASSERT_LE((a.dv - b.dv).norm(), 1e-11);
    ASSERT_LE((a.normal - b.normal).norm(), 1e-10);
  }
}

TEST(Nurbs, DerivativesMatchFiniteDifferences) {
  const NurbsSurface nurbs = torusNurbs(kTestTorus);
  const double h = 1e-6;
  for (double u : {0.1, 0.3, 0.55, 0.9})
    for (double v : {0.05, 0.4, 0.6, 0.8}) {
      const SurfacePoint s = nurbs.evaluate(u, v);
      const Eigen::Vector3d fu =
          (nurbs.evaluate(u + h, v).position - nurbs.evaluate(u - h, v).position) / (2 * h);
      const Eigen::Vector3d fv =
          (nurbs.evaluate(u, v + h).position - nurbs.evaluate(u, v - h).position) / (2 * h);
      EXPECT_LE((s.du - fu).norm(), 1e-6 * s.du.norm());
      EXPECT_LE((s.dv - fv).norm(), 1e-6 * s.dv.norm());
    }
}

TEST(Nurbs, InvalidInputThrows) {
  const std::vector<Eigen::Vector3d> p(4, Eigen::Vector3d::Zero());
  const std::vector<double> w(4, 1.0);
  const std::vector<double> k = {0, 0, 1, 1};
  EXPECT_NO_THROW(NurbsSurface(1, 1, k, k, 2, 2, p, w));
  EXPECT_THROW(NurbsSurface(1, 1, {0, 1, 0, 1}, k, 2, 2, p, w),
               InvalidParameterError);                                                // decreasing
  EXPECT_THROW(NurbsSurface(1, 1, {0, 0, 1}, k, 2, 2, p, w), InvalidParameterError);  // count
  EXPECT_THROW(NurbsSurface(1, 1, k, k, 2, 2, p, {1, 1, -1, 1}), InvalidParameterError);  // weight
  EXPECT_THROW(NurbsSurface(1, 1, k, k, 2, 2, {p[0]}, w), InvalidParameterError);
  EXPECT_THROW(NurbsSurface(2, 1, {0, 0.5, 0.5, 1, 1}, k, 2, 2, p, w),
               InvalidParameterError);  // not clamped
  const NurbsSurface s(1, 1, k, k, 2, 2, p, w);
  EXPECT_THROW(s.evaluate(1.5, 0.5), InvalidParameterError);
  EXPECT_THROW(torusQuarterPatch(kTestTorus, 0).evaluate(-0.1, 0.5), InvalidParameterError);
  EXPECT_THROW(torusQuarterPatch(TorusShape{1.0, 1.0}, 0), InvalidParameterError);
  EXPECT_THROW(torusQuarterPatch(TorusShape{1.0, -0.1}, 0), InvalidParameterError);
}

}  // namespace
}  // namespace slipfit
