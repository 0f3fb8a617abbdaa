// fitProfileCurve: polylines through noisy 2D samples of open and closed curves.

#include "slipfit/fitting/profile_curve.h"
#include "slipfit/sampling/random_vector.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace slipfit {
namespace {

/// N samples of a curve c(t), t uniform in [0, 1), moved by Gaussian noise σ along its normal.
template <class Curve>
Eigen::Matrix2Xd sampleCurve(Curve curve, int n, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  Eigen::Matrix2Xd q(2, n);
  for (int i = 0; i < n; ++i) {
    const double t = uniform(rng);
    const Eigen::Vector2d tangent = (curve(t + 1e-6) - curve(t - 1e-6)).normalized();
    q.col(i) = curve(t) + sigma * gauss(rng) * Eigen::Vector2d(-tangent.y(), tangent.x());
  }
  return q;
}

/// The largest distance from the fitted curve of exact samples of \a curve for t in [t0, t1].
template <class Curve>
double largestDeviation(const ProfileCurve& fitted, Curve curve, double t0, double t1) {
  double worst = 0.0;
  for (int k = 0; k <= 1000; ++k)
    worst = std::max(worst, profileDistance(fitted, curve(t0 + (t1 - t0) * k / 1000.0)));
  return worst;
}

const auto kSine = [](double t) {
  return Eigen::Vector2d(2.0 * t, 0.3 * std::sin(2.0 * M_PI * t));
};
const auto kEllipse = [](double t) {
  return Eigen::Vector2d(std::cos(2.0 * M_PI * t), 0.5 * std::sin(2.0 * M_PI * t));
};

// With noise σ across the curve the points' RMS distance from the fitted polyline is σ less the
// share of degrees of freedom it takes (2 V of N, V ≤ 60 here: under 3 %), and the polyline keeps
// within 1.5 σ of the true curve: Douglas–Peucker leaves up to σ from the refined polyline, whose
// vertices rest on about 8–30 points each (their own error σ / √8 at most; it is refined again
// after). Measured: 0.58–0.96 σ on the sine, 0.94–1.06 σ on the ellipse. Ends excluded: the last
// vertex may stop a few points short.
TEST(ProfileCurve, AnOpenCurveIsFollowedWithinItsNoise) {
  constexpr double kSigma = 0.005;
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const ProfileFit fit = fitProfileCurve(sampleCurve(kSine, 2000, kSigma, seed), kSigma);
    ASSERT_TRUE(fit.ok) << fit.reason;
    EXPECT_FALSE(fit.curve.closed);
    EXPECT_LE(fit.curve.vertices.size(), 60u) << "seed " << seed;
    EXPECT_NEAR(fit.rms_distance, kSigma, 0.1 * kSigma) << "seed " << seed;
    EXPECT_LE(largestDeviation(fit.curve, kSine, 0.02, 0.98), 1.5 * kSigma) << "seed " << seed;
  }
}

TEST(ProfileCurve, AClosedCurveIsClosed) {
  constexpr double kSigma = 0.005;
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const ProfileFit fit = fitProfileCurve(sampleCurve(kEllipse, 2000, kSigma, seed), kSigma);
    ASSERT_TRUE(fit.ok) << fit.reason;
    EXPECT_TRUE(fit.curve.closed) << "seed " << seed;
    EXPECT_NEAR(fit.rms_distance, kSigma, 0.1 * kSigma) << "seed " << seed;
    EXPECT_LE(largestDeviation(fit.curve, kEllipse, 0.0, 1.0), 1.5 * kSigma) << "seed " << seed;
  }
}

// A straight profile is the simplest polyline: two vertices (the Douglas–Peucker tolerance σ / 2
// is above the vertices' own scatter).
TEST(ProfileCurve, AStraightProfileHasTwoVertices) {
  constexpr double kSigma = 0.01;
  const auto line = [](double t) { return Eigen::Vector2d(3.0 * t, 1.0 + 0.5 * t); };
  const ProfileFit fit = fitProfileCurve(sampleCurve(line, 1500, kSigma, 4), kSigma);
  ASSERT_TRUE(fit.ok) << fit.reason;
  EXPECT_EQ(fit.curve.vertices.size(), 2u);
  EXPECT_NEAR(fit.rms_distance, kSigma, 0.1 * kSigma);
}

// Exact points: the chords of the circle stay within the simplification tolerance, b / 50, b the
// cell width (16 D / N for N = 2000 points on a bounding-box diagonal D = 2 √2).
TEST(ProfileCurve, ExactPointsOfACircleAreWithinTheChordTolerance) {
  const auto circle = [](double t) {
    return Eigen::Vector2d(std::cos(2.0 * M_PI * t), std::sin(2.0 * M_PI * t));
  };
  const ProfileFit fit = fitProfileCurve(sampleCurve(circle, 2000, 0.0, 5), 0.0);
  ASSERT_TRUE(fit.ok) << fit.reason;
  EXPECT_TRUE(fit.curve.closed);
  const double b = 16.0 * 2.0 * std::sqrt(2.0) / 2000.0;
  EXPECT_LE(fit.rms_distance, b / 50.0);
}

TEST(ProfileCurve, TooFewOrCoincidentPointsAreRefusedWithTheReason) {
  Eigen::Matrix2Xd few = Eigen::Matrix2Xd::Random(2, 9);
  ProfileFit fit = fitProfileCurve(few, 0.0);
  EXPECT_FALSE(fit.ok);
  EXPECT_NE(fit.reason.find("fewer than 10"), std::string::npos) << fit.reason;
  Eigen::Matrix2Xd spot = Eigen::Matrix2Xd::Ones(2, 50);
  fit = fitProfileCurve(spot, 0.0);
  EXPECT_FALSE(fit.ok);
  EXPECT_NE(fit.reason.find("one spot"), std::string::npos) << fit.reason;
}

// The helical metric and the periodic strip: the distance scales the first coordinate and takes
// the nearer image.
TEST(ProfileCurve, DistanceScalesTheFirstCoordinateAndWrapsThePeriod) {
  ProfileCurve c;
  c.vertices = {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(0.0, 1.0)};  // the segment x = 0
  EXPECT_DOUBLE_EQ(profileDistance(c, Eigen::Vector2d(0.4, 0.5)), 0.4);
  EXPECT_DOUBLE_EQ(profileDistance(c, Eigen::Vector2d(0.4, 0.5), 0.5), 0.2);
  EXPECT_NEAR(profileDistance(c, Eigen::Vector2d(0.9, 0.5), 1.0, 1.0), 0.1, 1e-15);
  EXPECT_DOUBLE_EQ(profileDistance(c, Eigen::Vector2d(0.0, 1.5)), 0.5);
}

// The index answers what the scan of every segment answers, bit for bit (distance, segment,
// parameter): on an open zigzag of 200 segments, a closed wavy ring of 300, a thread's profile on
// a periodic strip with the helical metric's scale 0.3–1, and a curve of one segment; queries near
// the curve, far from it and outside its box.
TEST(ProfileIndex, ProjectsAsTheScanOfEverySegment) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  struct Case {
    ProfileCurve curve;
    double period = 0.0;
    double min_scale = 1.0;
  };
  std::vector<Case> cases(4);
  for (int i = 0; i <= 200; ++i)
    cases[0].curve.vertices.emplace_back(0.01 * i, 0.05 * ((i % 7) - 3) + 0.3 * unit(rng) * 0.1);
  cases[1].curve.closed = true;
  for (int i = 0; i < 300; ++i) {
    const double a = 2.0 * M_PI * i / 300.0, r = 1.0 + 0.1 * std::sin(7.0 * a);
    cases[1].curve.vertices.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  const double period = 0.06;
  for (const auto& [u, rho] :
       {std::pair{0.0, 0.1}, {0.15, 0.1}, {0.4, 0.12}, {0.6, 0.12}, {0.85, 0.1}, {1.0, 0.1}})
    cases[2].curve.vertices.emplace_back(u * period, rho);
  cases[2].period = period;
  cases[2].min_scale = 0.3;
  cases[3].curve.vertices = {{0.0, 0.0}, {1.0, 0.5}};
  for (const Case& c : cases) {
    const ProfileIndex index(c.curve, c.period);
    Eigen::Vector2d lo = c.curve.vertices.front(), hi = lo;
    for (const Eigen::Vector2d& v : c.curve.vertices) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
    const Eigen::Vector2d size = (hi - lo).cwiseMax(Eigen::Vector2d::Constant(0.05));
    for (int k = 0; k < 3000; ++k) {
      // Near the curve (a vertex plus a little), in the box, or up to two boxes away.
      const Eigen::Vector2d& v = c.curve.vertices[static_cast<std::size_t>(
          unit(rng) * static_cast<double>(c.curve.vertices.size() - 1))];
      const double spread = k % 3 == 0 ? 0.01 : k % 3 == 1 ? 0.5 : 2.0;
      const Eigen::Vector2d w = randomVector<2>(unit, rng);
      const Eigen::Vector2d q =
          v + spread * Eigen::Vector2d((w(0) - 0.5) * size.x(), (w(1) - 0.5) * size.y());
      const double scale = c.min_scale + (1.0 - c.min_scale) * unit(rng);
      const ProfileProjection a = index.project(q, scale);
      const ProfileProjection b = projectOnProfile(c.curve, q, scale, c.period);
      ASSERT_EQ(a.distance, b.distance) << k;
      ASSERT_EQ(a.segment, b.segment) << k;
      ASSERT_EQ(a.t, b.t) << k;
      ASSERT_EQ(a.unit, b.unit) << k;
    }
  }
}

}  // namespace
}  // namespace slipfit
