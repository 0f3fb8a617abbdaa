#include "slipfit/fitting/robust_fit.h"

#include "expect_refused.h"
#include "slipfit/core/exceptions.h"
#include "slipfit/sampling/primitive_sampler.h"

#include <gtest/gtest.h>

#include <iostream>
#include <string>

namespace slipfit {
namespace {

TEST(RobustOptions, ValidateNamesTheFieldAndFitRobustChecksIt) {
  using testing::expectRefused;
  expectRefused<RobustOptions>("threshold", [](auto& o) { o.threshold = 0.0; });
  expectRefused<RobustOptions>("irls_iterations", [](auto& o) { o.irls_iterations = 0; });
  expectRefused<RobustOptions>("ransac_iterations", [](auto& o) { o.ransac_iterations = 0; });
  expectRefused<FitOptions>("max_iterations", [](auto& o) { o.max_iterations = 0; });
  expectRefused<FitOptions>("degenerate_rcond", [](auto& o) { o.degenerate_rcond = 1.0; });
  RobustOptions r;
  FitOptions f;
  f.degenerate_rcond = 1.0;
  const Eigen::Matrix3Xd p = Eigen::Matrix3Xd::Random(3, 20);
  r.ransac_iterations = 0;
  EXPECT_THROW(fitRobust(PrimitiveType::plane, p, p, Eigen::VectorXd::Ones(20), r),
               InvalidParameterError);
  EXPECT_THROW(fitPrimitive(PrimitiveType::plane, p, p, Eigen::VectorXd::Ones(20), f),
               InvalidParameterError);
}

struct Noisy {
  Eigen::Matrix3Xd x, n;
  std::vector<std::int32_t> outlier;
};

Noisy withOutliers(const Primitive& shape, double fraction, std::uint64_t seed) {
  PrimitiveSamplingParameters p;
  p.primitive = shape;
  p.points = 4000;
  p.noise = 0.005;
  p.extent = 1.5;
  p.outlier_fraction = fraction;
  p.seed = seed;
  Noisy s;
  samplePrimitive(p, s.x, s.n, &s.outlier);
  return s;
}

double radiusOf(const FitResult& r) {
  if (const auto* c = std::get_if<Cylinder>(&r.refined))
    return c->radius;
  return std::get<Sphere>(r.refined).radius;
}

TEST(RobustFit, OutliersPullThePlainFitButNotTheRobustOnes) {
  const Cylinder truth{Eigen::Vector3d(0.2, 0.1, 1).normalized(), Eigen::Vector3d(1, 2, 3), 0.5};
  const Noisy s = withOutliers(truth, 0.3, 3);
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(s.x.cols());
  RobustOptions none;
  none.method = RobustMethod::none;
  const FitResult plain = fitRobust(PrimitiveType::cylinder, s.x, s.n, w, none);
  ASSERT_TRUE(plain.ok());
  const double plain_error = std::abs(radiusOf(plain) / 0.5 - 1);

  for (const auto method : {RobustMethod::irls, RobustMethod::ransac}) {
    RobustOptions o;
    o.method = method;
    std::vector<char> inliers;
    double limit = 0.0;
    const FitResult r = fitRobust(PrimitiveType::cylinder, s.x, s.n, w, o, {}, &inliers, &limit);
    ASSERT_TRUE(r.ok()) << r.reason;
    const double error = std::abs(radiusOf(r) / 0.5 - 1);
    EXPECT_LT(error, 0.01) << (method == RobustMethod::irls ? "irls" : "ransac");
    EXPECT_LT(3 * error, plain_error) << "the robust fit must beat the plain one clearly";
    std::size_t true_in = 0, false_in = 0, surface = 0, outliers = 0;
    for (std::size_t i = 0; i < inliers.size(); ++i) {
      (s.outlier[i] ? outliers : surface) += 1;
      (s.outlier[i] ? false_in : true_in) += inliers[i] ? 1 : 0;
    }
    EXPECT_GT(true_in, surface * 95 / 100);
    // Uniform outliers in the box land in the ±2.5σ band around the surface by chance: the band is
    // about 7 % of the box's volume here.
    EXPECT_LT(false_in, outliers * 10 / 100);
    EXPECT_GT(limit, 0.0);
  }
}

TEST(RobustFit, RansacSurvivesMostlyOutliersAndIsSeeded) {
  const Sphere truth{Eigen::Vector3d(-1, 0.5, 2), 0.7};
  const Noisy s = withOutliers(truth, 1.0, 5);  // as many outliers as surface points
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(s.x.cols());
  RobustOptions o;
  o.method = RobustMethod::ransac;
  o.seed = 42;
  const FitResult a = fitRobust(PrimitiveType::sphere, s.x, s.n, w, o);
  ASSERT_TRUE(a.ok());
  EXPECT_LT(std::abs(radiusOf(a) / 0.7 - 1), 0.01);
  EXPECT_LT((std::get<Sphere>(a.refined).center - truth.center).norm(), 0.01);
  const FitResult b = fitRobust(PrimitiveType::sphere, s.x, s.n, w, o);
  EXPECT_EQ(std::get<Sphere>(a.refined).radius, std::get<Sphere>(b.refined).radius)
      << "same seed, same answer";
}

// fitRobustAuto: with 30 % outliers in the bounding box, each shape is returned as its own type
// — the one whose robust fit holds the most weight within the common distance, the simpler within
// 1 % — and a plane is not a sphere in its flat limit (the sphere's fit holds the same points).
TEST(RobustFit, AutoTypeIsTheShapesTypeDespiteOutliers) {
  const std::vector<std::pair<Primitive, PrimitiveType>> shapes = {
      {Plane{Eigen::Vector3d(0.1, -0.2, 1).normalized(), 0.4}, PrimitiveType::plane},
      {Sphere{Eigen::Vector3d(1, 0, 2), 0.7}, PrimitiveType::sphere},
      {Cylinder{Eigen::Vector3d(0.2, 0.1, 1).normalized(), Eigen::Vector3d(1, 2, 3), 0.5},
       PrimitiveType::cylinder}};
  for (const auto& [shape, type] : shapes) {
    const Noisy s = withOutliers(shape, 0.3, 5);
    double limit = 0.0;
    RobustOptions ransac;
    ransac.method = RobustMethod::ransac;
    const FitResult r =
        fitRobustAuto(s.x, s.n, Eigen::VectorXd::Ones(s.x.cols()), ransac, {}, &limit);
    ASSERT_TRUE(r.ok()) << r.reason;
    EXPECT_EQ(r.type, type) << primitiveTypeName(type);
    // The common distance: 2.5 × the robust scale 1.4826 · median |D|, whose median also counts
    // the 30 % outliers (measured 3.5–3.7 σ for σ = 0.005), below 5 σ; the outliers spread over
    // the whole 1.5-wide box.
    EXPECT_GT(limit, 0.0);
    std::cout << primitiveTypeName(type) << ": common inlier distance " << limit << "\n";
    EXPECT_LT(limit, 5 * 0.005) << primitiveTypeName(type);
  }
}

}  // namespace
}  // namespace slipfit
