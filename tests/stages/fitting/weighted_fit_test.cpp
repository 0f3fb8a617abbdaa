// CGAL-style checks of the weighted estimators: random primitives in random poses, recovered
// against the generating parameters with tolerances from the noise level.
#include "slipfit/fitting/weighted_fit.h"
#include "shared_neighborhoods.h"
#include "slipfit/core/angle_units.h"
#include "slipfit/sampling/primitive_sampler.h"
#include "slipfit/sampling/random_vector.h"
#include "slipfit/sampling/range_scanner.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <cmath>
#include <iostream>
#include <random>
#include <type_traits>

namespace slipfit {
namespace {

/// A random primitive of \a type, size ~ \a size, placed within \a offset of the origin.
Primitive randomPrimitive(PrimitiveType type, std::mt19937_64& rng, double size, double offset) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), pos(0.5, 1.5);
  auto dir = [&] { return randomVector<3>(u, rng).normalized(); };
  const Eigen::Vector3d where = offset * Eigen::Vector3d::Ones() + size * randomVector<3>(u, rng);
  switch (type) {
    case PrimitiveType::plane: {
      const Eigen::Vector3d n = dir();
      return Plane{n, n.dot(where)};
    }
    case PrimitiveType::sphere:
      return Sphere{where, size * pos(rng)};
    case PrimitiveType::cylinder:
      return Cylinder{dir(), where, size * pos(rng)};
    case PrimitiveType::cone:
      return Cone{dir(), where, (15 + 40 * (u(rng) + 1) / 2) * kDegree};
    case PrimitiveType::torus: {
      const double major = size * pos(rng);  // r/R in [0.1, 0.6]
      return Torus{dir(), where, major, major * (0.1 + 0.25 * (u(rng) + 1))};
    }
  }
  return Plane{};
}

struct Sample {
  Eigen::Matrix3Xd points, normals;
  Eigen::VectorXd weights;
};

Sample sample(const Primitive& shape, double size, double noise_fraction, std::uint64_t seed,
              std::size_t n = 4000) {
  PrimitiveSamplingParameters p;
  p.primitive = shape;
  p.points = n;
  p.extent = size;
  p.noise = noise_fraction * size;
  p.seed = seed;
  if (std::holds_alternative<Cylinder>(shape))
    p.extent = 2 * size;
  if (const auto* c = std::get_if<Cylinder>(&shape))
    p.extent_min = 0, (void)c;
  Sample s;
  samplePrimitive(p, s.points, s.normals);
  s.weights = Eigen::VectorXd::Ones(static_cast<Eigen::Index>(n));
  return s;
}

double axisAngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized())))) / kDegree;
}

/// Largest relative parameter error between a fit and the truth (directions: sine of the angle;
/// positions: distance relative to \a size).
double parameterError(const Primitive& fit, const Primitive& truth, double size) {
  return std::visit(
      [&](const auto& t) -> double {
        using T = std::decay_t<decltype(t)>;
        const T& f = std::get<T>(fit);
        if constexpr (std::is_same_v<T, Plane>) {
          const double sign = f.normal.dot(t.normal) < 0 ? -1.0 : 1.0;
          return std::max((sign * f.normal - t.normal).norm(), std::abs(sign * f.d - t.d) / size);
        } else if constexpr (std::is_same_v<T, Sphere>) {
          return std::max((f.center - t.center).norm() / size,
                          std::abs(f.radius - t.radius) / t.radius);
        } else if constexpr (std::is_same_v<T, Cylinder>) {
          const Eigen::Vector3d v = f.point - t.point;  // must lie on the true axis
          return std::max({std::sin(axisAngleDeg(f.axis, t.axis) * kDegree),
                           (v - v.dot(t.axis) * t.axis).norm() / size,
                           std::abs(f.radius - t.radius) / t.radius});
        } else if constexpr (std::is_same_v<T, Torus>) {
          // sin of the axis angle as ‖a × b‖ (acos near 1 loses half the digits)
          return std::max({f.axis.normalized().cross(t.axis.normalized()).norm(),
                           (f.center - t.center).norm() / size,
                           std::abs(f.major_radius - t.major_radius) / t.major_radius,
                           std::abs(f.minor_radius - t.minor_radius) / t.minor_radius});
        } else {
          return std::max({(f.axis - t.axis).norm(), (f.apex - t.apex).norm() / size,
                           std::abs(f.half_angle - t.half_angle) / t.half_angle});
        }
      },
      truth);
}

class RandomPoses : public ::testing::TestWithParam<PrimitiveType> {};

TEST_P(RandomPoses, NoiseFreeRecoveryAcrossScalesAndOffsets) {
  std::mt19937_64 rng(100 + static_cast<int>(GetParam()));
  for (const auto& [size, offset] : {std::pair{1.0, 0.0}, std::pair{1e-3, 0.0}, std::pair{1e3, 0.0},
                                     std::pair{1.0, 1e4}, std::pair{1e-3, 1e4}}) {
    for (int trial = 0; trial < 10; ++trial) {
      const Primitive truth = randomPrimitive(GetParam(), rng, size, offset);
      const Sample s = sample(truth, size, 0.0, 1000 + trial);
      const FitResult r = fitPrimitive(GetParam(), s.points, s.normals, s.weights);
      ASSERT_TRUE(r.ok()) << r.reason;
      // 1e-9 relative; but coordinates at an offset carry offset × 2.2e-16 of rounding, which
      // for a 1e-3 object at 1e4 is already 2.2e-9 of its size: allow 50 times that.
      const double tol = std::max(1e-9, 50 * offset * 2.2e-16 / size);
      EXPECT_LT(parameterError(r.algebraic, truth, size), tol)
          << "closed form, size " << size << " offset " << offset;
      EXPECT_LT(parameterError(r.refined, truth, size), tol)
          << "refined, size " << size << " offset " << offset;
      EXPECT_LE(r.loss_refined, r.loss_algebraic);
    }
  }
}

/// \a truth moved by about 1 %: directions tilted by 0.6°, positions by 1 % of \a size, radii
/// and the cone's angle by 1 %.
Primitive perturbed(const Primitive& truth, double size) {
  const Eigen::Vector3d shift = 0.01 * size * Eigen::Vector3d(0.6, -0.5, 0.62);
  const auto tilt = [](const Eigen::Vector3d& d) {
    return Eigen::Vector3d(d + 0.01 * d.unitOrthogonal()).normalized();
  };
  return std::visit(
      [&](auto s) -> Primitive {
        using T = decltype(s);
        if constexpr (std::is_same_v<T, Plane>) {
          s.normal = tilt(s.normal);
          s.d += 0.01 * size;
        } else if constexpr (std::is_same_v<T, Sphere>) {
          s.center += shift;
          s.radius *= 1.01;
        } else if constexpr (std::is_same_v<T, Cylinder>) {
          s.axis = tilt(s.axis);
          s.point += shift;
          s.radius *= 1.01;
        } else if constexpr (std::is_same_v<T, Cone>) {
          s.axis = tilt(s.axis);
          s.apex += shift;
          s.half_angle *= 1.01;
        } else {
          s.axis = tilt(s.axis);
          s.center += shift;
          s.major_radius *= 1.01;
          s.minor_radius *= 1.01;
        }
        return s;
      },
      truth);
}

// Levenberg–Marquardt on the exact Jacobian of the distances: on noise-free points Gauss–Newton
// converges quadratically (1e-2, 1e-4, 1e-8, 1e-16), so from a start 1 % off the truth a dozen
// step evaluations reach the closed forms' 1e-9. A wrong derivative slows it to linear
// convergence at best (measured: a sign error in the cylinder's axis term leaves errors of
// 1e-2, the start's).
TEST_P(RandomPoses, RefinementFromOnePercentOffConvergesInAFewSteps) {
  std::mt19937_64 rng(700 + static_cast<int>(GetParam()));
  for (int trial = 0; trial < 10; ++trial) {
    const Primitive truth = randomPrimitive(GetParam(), rng, 1.0, 0.0);
    const Sample s = sample(truth, 1.0, 0.0, 3000 + trial);
    int iterations = 0;
    const Primitive refined =
        refinePrimitive(perturbed(truth, 1.0), s.points, s.weights, 12, &iterations);
    EXPECT_LT(parameterError(refined, truth, 1.0), 1e-9) << "trial " << trial;
    EXPECT_LE(iterations, 12) << "trial " << trial;
  }
}

// fitFrom, the warm start the segmentation's merge tries first: from a start 1 % off, on
// noise-free points it ends on the truth (the refinement's quadratic convergence, as above), and
// on points with 1 % noise on the same least-squares minimum as fitPrimitive from its closed form
// (both stop when a step changes the loss by less than 1e-14 of it: their losses agree to far
// better than 1e-6). The start is kept as the result's algebraic primitive.
TEST_P(RandomPoses, FitFromAStartOnePercentOffEndsOnTheClosedFormsMinimum) {
  std::mt19937_64 rng(750 + static_cast<int>(GetParam()));
  for (int trial = 0; trial < 10; ++trial) {
    const Primitive truth = randomPrimitive(GetParam(), rng, 1.0, 2.0);
    const Primitive start = perturbed(truth, 1.0);
    const Sample exact = sample(truth, 1.0, 0.0, 3100 + trial);
    const FitResult r = fitFrom(start, exact.points, exact.weights);
    ASSERT_TRUE(r.ok()) << r.reason;
    EXPECT_EQ(r.type, GetParam());
    EXPECT_EQ(r.loss_algebraic, weightedLoss(exact.points, exact.weights, start));
    EXPECT_EQ(weightedLoss(exact.points, exact.weights, r.algebraic), r.loss_algebraic);
    EXPECT_LT(parameterError(r.refined, truth, 1.0), 1e-9) << "trial " << trial;
    EXPECT_LT(r.rms_distance, 1e-9) << "trial " << trial;
    EXPECT_EQ(r.used_points, static_cast<std::size_t>(exact.points.cols()));

    const Sample noisy = sample(truth, 1.0, 0.01, 3200 + trial);
    const FitResult warm = fitFrom(start, noisy.points, noisy.weights);
    const FitResult cold = fitPrimitive(GetParam(), noisy.points, noisy.normals, noisy.weights);
    ASSERT_TRUE(warm.ok() && cold.ok()) << warm.reason << cold.reason;
    EXPECT_LE(warm.loss_refined, warm.loss_algebraic);
    EXPECT_NEAR(warm.loss_refined, cold.loss_refined, 1e-6 * cold.loss_refined)
        << "trial " << trial;
    EXPECT_NEAR(warm.rms_distance, std::sqrt(warm.loss_refined / noisy.points.cols()), 1e-15);
  }
}

TEST(WeightedFit, FitFromRefusesANonFiniteStartAndTooFewPoints) {
  const Eigen::Matrix3Xd points = Eigen::Matrix3Xd::Random(3, 10);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(10);
  const Cylinder nan{Eigen::Vector3d::UnitZ(), Eigen::Vector3d(std::nan(""), 0, 0), 1.0};
  const FitResult bad = fitFrom(nan, points, ones);
  EXPECT_EQ(bad.status, FitStatus::invalid_input);
  EXPECT_FALSE(bad.reason.empty());
  const Cylinder c{Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(), 1.0};
  const FitResult few = fitFrom(c, points.leftCols(4), ones.head(4));
  EXPECT_EQ(few.status, FitStatus::too_few_points) << "a cylinder needs 5 points";
  EXPECT_EQ(fitFrom(c, points, ones.head(9)).status, FitStatus::invalid_input);
}

TEST_P(RandomPoses, OnePercentNoise) {
  std::mt19937_64 rng(200 + static_cast<int>(GetParam()));
  for (int trial = 0; trial < 20; ++trial) {
    const Primitive truth = randomPrimitive(GetParam(), rng, 1.0, 5.0);
    const Sample s = sample(truth, 1.0, 0.01, 3000 + trial, 5000);
    const FitResult r = fitPrimitive(GetParam(), s.points, s.normals, s.weights);
    ASSERT_TRUE(r.ok()) << r.reason;
    const Primitive& f = r.refined;
    std::visit(
        [&](const auto& t) {
          using T = std::decay_t<decltype(t)>;
          const T& g = std::get<T>(f);
          if constexpr (std::is_same_v<T, Plane>)
            EXPECT_LT(axisAngleDeg(g.normal, t.normal), 1.0);
          if constexpr (std::is_same_v<T, Sphere>)
            EXPECT_LT(std::abs(g.radius / t.radius - 1), 0.01);
          if constexpr (std::is_same_v<T, Cylinder>) {
            EXPECT_LT(std::abs(g.radius / t.radius - 1), 0.01);
            EXPECT_LT(axisAngleDeg(g.axis, t.axis), 1.0);
          }
          if constexpr (std::is_same_v<T, Cone>) {
            EXPECT_LT(std::abs(g.half_angle - t.half_angle) / kDegree, 1.0);
            EXPECT_LT(axisAngleDeg(g.axis, t.axis), 1.0);
          }
          if constexpr (std::is_same_v<T, Torus>) {
            EXPECT_LT(std::abs(g.major_radius / t.major_radius - 1), 0.01);
            EXPECT_LT(std::abs(g.minor_radius / t.minor_radius - 1),
                      0.01 * t.major_radius / t.minor_radius);
            EXPECT_LT(axisAngleDeg(g.axis, t.axis), 1.0);
          }
        },
        truth);
    EXPECT_LT(r.rms_distance, 0.02 * 1.8);  // σ√3 for isotropic noise, plus slack
  }
}

TEST_P(RandomPoses, ZeroWeightGarbageDoesNotChangeTheFit) {
  std::mt19937_64 rng(300 + static_cast<int>(GetParam()));
  const Primitive truth = randomPrimitive(GetParam(), rng, 1.0, 2.0);
  Sample s = sample(truth, 1.0, 0.005, 77);
  const FitResult clean = fitPrimitive(GetParam(), s.points, s.normals, s.weights);
  const Eigen::Index n = s.points.cols();
  Sample g;
  g.points = Eigen::Matrix3Xd::Random(3, n + 500) * 50.0;
  g.normals = Eigen::Matrix3Xd::Random(3, n + 500);
  g.weights = Eigen::VectorXd::Zero(n + 500);
  g.points.leftCols(n) = s.points;
  g.normals.leftCols(n) = s.normals;
  g.weights.head(n) = s.weights;
  g.points(0, n + 3) = std::numeric_limits<double>::quiet_NaN();  // ignored: weight 0
  const FitResult dirty = fitPrimitive(GetParam(), g.points, g.normals, g.weights);
  ASSERT_TRUE(dirty.ok()) << dirty.reason;
  EXPECT_EQ(parameterError(dirty.algebraic, clean.algebraic, 1.0), 0.0);
  EXPECT_EQ(parameterError(dirty.refined, clean.refined, 1.0), 0.0);
}

TEST_P(RandomPoses, AutoSelectsTheType) {
  std::mt19937_64 rng(400 + static_cast<int>(GetParam()));
  for (const double noise : {0.0, 0.005}) {
    for (int trial = 0; trial < 5; ++trial) {
      const Primitive truth = randomPrimitive(GetParam(), rng, 1.0, 3.0);
      const Sample s = sample(truth, 1.0, noise, 500 + trial);
      const FitResult r = fitAuto(s.points, s.normals, s.weights);
      ASSERT_TRUE(r.ok()) << r.reason;
      EXPECT_EQ(r.type, GetParam())
          << "noise " << noise << " trial " << trial << ": got " << primitiveTypeName(r.type);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Types, RandomPoses,
                         ::testing::Values(PrimitiveType::plane, PrimitiveType::sphere,
                                           PrimitiveType::cylinder, PrimitiveType::cone,
                                           PrimitiveType::torus),
                         [](const auto& info) {
                           return std::string(primitiveTypeName(info.param));
                         });

TEST(WeightedFit, PartialCoverage) {
  // A 60° strip of a cylinder, a 40° spherical cap, a cone band away from the apex; 0.2 % noise.
  PrimitiveSamplingParameters p;
  p.points = 5000;
  p.noise = 0.002;
  p.seed = 9;
  Eigen::Matrix3Xd x, n;
  const Cylinder cyl{Eigen::Vector3d(1, 2, 3).normalized(), Eigen::Vector3d(1, 0, 0), 1.0};
  p.primitive = cyl;
  p.extent = 2.0;
  p.angle_max = 60 * kDegree;
  samplePrimitive(p, x, n);
  FitResult r = fitPrimitive(PrimitiveType::cylinder, x, n, Eigen::VectorXd::Ones(x.cols()));
  ASSERT_TRUE(r.ok()) << r.reason;
  EXPECT_LT(std::abs(std::get<Cylinder>(r.refined).radius - 1.0), 0.01);
  EXPECT_LT(axisAngleDeg(std::get<Cylinder>(r.refined).axis, cyl.axis), 1.0);
  EXPECT_LT(r.loss_refined, r.loss_algebraic) << "refinement must help on partial noisy data";

  const Sphere sph{Eigen::Vector3d(-2, 1, 0.5), 1.0};
  p = PrimitiveSamplingParameters{};
  p.primitive = sph;
  p.points = 5000;
  p.noise = 0.002;
  p.cap = 40 * kDegree;
  p.axis_hint = Eigen::Vector3d(0, 1, 1);
  samplePrimitive(p, x, n);
  r = fitPrimitive(PrimitiveType::sphere, x, n, Eigen::VectorXd::Ones(x.cols()));
  ASSERT_TRUE(r.ok()) << r.reason;
  EXPECT_LT(std::abs(std::get<Sphere>(r.refined).radius - 1.0), 0.01);
  EXPECT_LE(r.loss_refined, r.loss_algebraic);

  const Cone cone{Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0.3, 0.1, -1), 30 * kDegree};
  p = PrimitiveSamplingParameters{};
  p.primitive = cone;
  p.points = 5000;
  p.noise = 0.002;
  p.extent_min = 1.0;
  p.extent = 2.0;
  samplePrimitive(p, x, n);
  r = fitPrimitive(PrimitiveType::cone, x, n, Eigen::VectorXd::Ones(x.cols()));
  ASSERT_TRUE(r.ok()) << r.reason;
  EXPECT_LT(std::abs(std::get<Cone>(r.refined).half_angle - cone.half_angle) / kDegree, 1.0);
  EXPECT_LT((std::get<Cone>(r.refined).apex - cone.apex).norm(), 0.05);
  EXPECT_LE(r.loss_refined, r.loss_algebraic);
}

// One side of a wide cone as a terrestrial LiDAR sees it: a sand pile (half angle 51°, 2.1 m
// high) 8 m from the scanner, 5 mm range noise along the rays, normals by PCA of 12 neighbours —
// the segmentation's input — and a 50° wedge of it around the axis, as a region holds it while it
// grows. The tangent planes of the wedge are nearly parallel and its PCA normals lean away from
// the rays, so the apex they meet is ill-posed: the fit from that apex alone ends on a sideways
// cone (axis 76° and 68° off on seeds 1 and 2; RMS 8.9 mm on seed 1, 2.5 times the right cone's).
// The second start, from the axis every normal line meets, ends on the pile's cone: over these
// seeds its axis is at most 0.24° off, its half angle 0.23°, its apex 22 mm, and its RMS 3.7 mm.
// The bounds are about ten times the angles, five times the apex, and the range noise itself for
// the RMS (noise along the ray is no larger across the surface).
TEST(WeightedFit, OneSideOfAWideConeUnderLidarNoiseFindsItsAxis) {
  const Cone pile{-Eigen::Vector3d::UnitZ(), Eigen::Vector3d(-5.7, -5.7, 2.1), 51 * kDegree};
  SensorScene scene;
  scene.pieces.push_back(coneBand(pile.apex, pile.axis, pile.half_angle, 0.0, pile.apex.z()));
  scene.focus = Eigen::Vector3d::Zero();
  scene.extent = 30.0;
  RangeSensorParameters sensor;
  sensor.sensor = RangeSensorKind::lidar;
  sensor.truth_min_points = 1;
  for (std::uint64_t seed : {1u, 2u, 3u, 4u}) {
    const RangeScan scan = scanScene(scene, sensor, seed);
    auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointNormal>>();
    for (Eigen::Index i = 0; i < scan.points.cols(); ++i)
      if (scan.points.col(i).allFinite()) {
        pcl::PointNormal q;
        q.getVector3fMap() = scan.points.col(i).cast<float>();
        cloud->push_back(q);
      }
    testing::estimateNormals(cloud, testing::knnNeighborhoods(cloud, 12));
    // The wedge: 50° of azimuth about the pile's axis, centred on the scanner's side.
    const double facing = std::atan2(-pile.apex.y(), -pile.apex.x());
    std::vector<Eigen::Index> wedge;
    for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(cloud->size()); ++i) {
      const Eigen::Vector3d v = (*cloud)[i].getVector3fMap().cast<double>() - pile.apex;
      const double off = std::remainder(std::atan2(v.y(), v.x()) - facing + 0.3, 2 * kPi);
      if (std::abs(off) < 25 * kDegree)
        wedge.push_back(i);
    }
    ASSERT_GT(wedge.size(), 1000u);
    Eigen::Matrix3Xd x(3, static_cast<Eigen::Index>(wedge.size())), n(3, x.cols());
    for (Eigen::Index j = 0; j < x.cols(); ++j) {
      x.col(j) = (*cloud)[wedge[j]].getVector3fMap().cast<double>();
      n.col(j) = (*cloud)[wedge[j]].getNormalVector3fMap().cast<double>();
    }
    const FitResult r = fitPrimitive(PrimitiveType::cone, x, n, Eigen::VectorXd::Ones(x.cols()));
    ASSERT_TRUE(r.ok()) << r.reason;
    const auto& fit = std::get<Cone>(r.refined);
    EXPECT_LT(axisAngleDeg(fit.axis, pile.axis), 3.0) << "seed " << seed;
    EXPECT_LT(std::abs(fit.half_angle - pile.half_angle) / kDegree, 2.0) << "seed " << seed;
    EXPECT_LT((fit.apex - pile.apex).norm(), 0.1) << "seed " << seed;
    EXPECT_LT(r.rms_distance, 0.005) << "seed " << seed;
  }
}

TEST(WeightedFit, NormalSignFlipsDoNotMatter) {
  PrimitiveSamplingParameters p;
  p.primitive = Cone{Eigen::Vector3d(1, 1, 0).normalized(), Eigen::Vector3d(0, 0, 0), 25 * kDegree};
  p.points = 3000;
  p.flip_fraction = 0.5;
  p.extent_min = 0.5;
  Eigen::Matrix3Xd x, n;
  samplePrimitive(p, x, n);
  const FitResult r = fitPrimitive(PrimitiveType::cone, x, n, Eigen::VectorXd::Ones(x.cols()));
  ASSERT_TRUE(r.ok()) << r.reason;
  EXPECT_LT(parameterError(r.refined, p.primitive, 1.0), 1e-9);
}

TEST(WeightedFit, DegenerateInputIsReportedNeverNaN) {
  const Eigen::VectorXd w3 = Eigen::VectorXd::Ones(3);
  Eigen::Matrix3Xd line(3, 10), none(3, 0);
  for (int i = 0; i < 10; ++i)
    line.col(i) = Eigen::Vector3d(i, 2 * i, -i);
  EXPECT_EQ(estimatePlane(line, Eigen::VectorXd::Ones(10)).status, FitStatus::degenerate);
  EXPECT_EQ(estimatePlane(line.leftCols(2), Eigen::VectorXd::Ones(2)).status,
            FitStatus::too_few_points);
  EXPECT_EQ(estimatePlane(line, Eigen::VectorXd::Zero(10)).status, FitStatus::zero_weight);
  Eigen::VectorXd neg = Eigen::VectorXd::Ones(10);
  neg[3] = -1;
  EXPECT_EQ(estimatePlane(line, neg).status, FitStatus::invalid_input);
  EXPECT_EQ(estimatePlane(line, w3).status, FitStatus::invalid_input);  // size mismatch

  // A plane given to the sphere estimator: infinite radius.
  PrimitiveSamplingParameters p;
  p.primitive = Plane{Eigen::Vector3d(0, 0, 1), 2.0};
  p.points = 100;
  Eigen::Matrix3Xd x, n;
  samplePrimitive(p, x, n);
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(100);
  FitResult r = estimateSphere(x, w);
  EXPECT_EQ(r.status, FitStatus::degenerate);
  EXPECT_NE(r.reason.find("coplanar"), std::string::npos);
  // Parallel normals: no cone apex, no cylinder axis.
  EXPECT_EQ(estimateCone(x, n, w).status, FitStatus::degenerate);
  EXPECT_EQ(estimateCylinder(x, n, w).status, FitStatus::degenerate);
  // A cylinder's normals never meet in one point.
  p.primitive = Cylinder{};
  samplePrimitive(p, x, n);
  EXPECT_EQ(estimateCone(x, n, w).status, FitStatus::degenerate);
  // NaN with positive weight.
  x(1, 7) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(fitPrimitive(PrimitiveType::sphere, x, n, w).status, FitStatus::invalid_input);
  EXPECT_EQ(fitAuto(none, none, Eigen::VectorXd()).status, FitStatus::degenerate);
}

TEST(Distances, MatchBruteForceNearestPoints) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  const Primitive shapes[] = {
      Plane{Eigen::Vector3d(1, 2, 2) / 3.0, 0.5}, Sphere{Eigen::Vector3d(0.2, 0, 0), 1.2},
      Cylinder{Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 0, 0.3), 0.8},
      Cone{Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, -0.5), 35 * kDegree}};
  for (const auto& shape : shapes) {
    // A fine sampling of a large piece of the surface (whole sphere, ±8 around the others).
    PrimitiveSamplingParameters p;
    p.primitive = shape;
    p.points = 400000;
    p.extent = 8.0;
    p.extent_min = 0.0;
    if (std::holds_alternative<Cylinder>(shape))
      p.extent_min = 0.0;
    Eigen::Matrix3Xd x, n;
    samplePrimitive(p, x, n);
    if (auto* c = std::get_if<Cylinder>(&shape))
      x.colwise() -= 4.0 * c->axis;  // heights −4..4
    int behind_apex = 0;
    for (int q = 0; q < 60; ++q) {
      const Eigen::Vector3d query = randomVector<3>(u, rng);
      const double brute = (x.colwise() - query).colwise().norm().minCoeff();
      const double exact = distance(query, shape);
      // Brute force is an upper bound, within the sample spacing (~0.05 here) of the truth.
      EXPECT_LE(exact, brute + 1e-12) << primitiveTypeName(typeOf(shape));
      EXPECT_NEAR(exact, brute, 0.06) << primitiveTypeName(typeOf(shape));
      if (const auto* c = std::get_if<Cone>(&shape))
        behind_apex += (query - c->apex).dot(c->axis) < -std::tan(c->half_angle) * 0 - 0.5 ? 1 : 0;
    }
    if (std::holds_alternative<Cone>(shape))
      EXPECT_GT(behind_apex, 5) << "no query exercised the apex case";
  }
  // The apex case exactly: a point straight behind the apex.
  const Cone c{Eigen::Vector3d(0, 0, 1), Eigen::Vector3d::Zero(), 30 * kDegree};
  EXPECT_DOUBLE_EQ(distance(Eigen::Vector3d(0, 0, -2), c), 2.0);
  EXPECT_NEAR(distance(Eigen::Vector3d(1, 0, 0), c), std::cos(30 * kDegree), 1e-15);
}

/// A band of \a arc radians of a cylinder of radius 4 about the z axis through (0, 0, 3), 2 long,
/// \a n points drawn uniformly over it, each normal turned by a random angle of \a normal_noise
/// radians (PCA normals of a CAD part: bent near the band's edges).
struct Band {
  Eigen::Matrix3Xd points, normals;
};
Band cylinderBand(double arc, int n, double normal_noise, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  Band b;
  b.points.resize(3, n);
  b.normals.resize(3, n);
  for (int i = 0; i < n; ++i) {
    const double t = arc * (u(rng) - 0.5), z = 2.0 * u(rng);
    const Eigen::Vector3d radial(std::cos(t), std::sin(t), 0.0);
    b.points.col(i) = Eigen::Vector3d(0.0, 0.0, 3.0) + 4.0 * radial + z * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d turn = randomVector<3>(g, rng);
    b.normals.col(i) = (radial + normal_noise * (turn - turn.dot(radial) * radial)).normalized();
  }
  return b;
}

// The axis the normal lines meet is exact on exact data, as the closed forms are.
TEST(WeightedFit, ACylinderFromTheAxisItsNormalLinesMeetIsExactOnExactData) {
  const Band b = cylinderBand(1.0, 200, 0.0, 3);
  const FitResult r =
      estimateCylinderAboutAxis(b.points, b.normals, Eigen::VectorXd::Ones(b.points.cols()));
  ASSERT_TRUE(r.ok()) << r.reason;
  const auto& c = std::get<Cylinder>(r.algebraic);
  EXPECT_NEAR(std::abs(c.axis.z()), 1.0, 1e-12);
  EXPECT_NEAR(c.radius, 4.0, 1e-9);
  EXPECT_NEAR(Eigen::Vector2d(c.point.x(), c.point.y()).norm(), 0.0, 1e-9);
}

// A band of 5.7° (0.1 rad) of a radius-4 cylinder, 2 long, with normals 5° off (Fit4CAD PC167's
// bands: 6°, PCA normals): Σ nnᵀ's least direction, estimateCylinder's axis, is set by the
// normals' noise as much as by the band's fan across the axis (0.1²/12 = 8e-4 against the noise's
// 0.087² = 0.0076), and the refinement from it runs out to the flat limit in 7 of 20 draws
// (measured). fitPrimitive's second start, from the axis the normal lines meet (positions fix
// that line), gives the band's cylinder in 19 of the 20; in the last both starts end flat.
TEST(WeightedFit, ANarrowBandOfAWideCylinderIsFoundFromTheAxisItsNormalLinesMeet) {
  int found = 0, found_first = 0;
  const auto isTheBand = [](const Primitive& p) {
    const auto* c = std::get_if<Cylinder>(&p);
    // Exact positions: the band's cylinder to the refinement's stopping rule.
    return c && std::abs(c->radius - 4.0) < 1e-6 && std::abs(std::abs(c->axis.z()) - 1.0) < 1e-9;
  };
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const Band b = cylinderBand(0.1, 180, 5.0 * kDegree, seed);
    const Eigen::VectorXd w = Eigen::VectorXd::Ones(b.points.cols());
    const FitResult first = estimateCylinder(b.points, b.normals, w);
    if (first.ok())
      found_first += isTheBand(refinePrimitive(first.algebraic, b.points, w, 100)) ? 1 : 0;
    const FitResult r = fitPrimitive(PrimitiveType::cylinder, b.points, b.normals, w);
    ASSERT_TRUE(r.ok()) << r.reason;
    found += isTheBand(r.refined) ? 1 : 0;
  }
  std::cout << "the band's cylinder in " << found << " of 20 draws, from the first start alone in "
            << found_first << "\n";
  EXPECT_GE(found, 19);
  EXPECT_LE(found_first, 13) << "the case the second start is for did not occur";
}

}  // namespace
}  // namespace slipfit
