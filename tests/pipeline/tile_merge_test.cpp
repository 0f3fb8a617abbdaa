// The refit of a segment joined across tiles (tile_merge.h): where the closed form on the pieces'
// samples fails — its normals do not determine a cone — the largest piece's fit, refined on the
// samples, is the fit; a start of another type is not taken.
#include "tiling/tile_merge.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>

namespace slipfit::pipeline::tiling {
namespace {

TEST(TileMerge, AJoinedConeWhoseNormalsFailTheClosedFormIsRefinedFromItsLargestPiece) {
  // The fixed scene's cone: apex (1, 1, 1), opening down, base radius 0.45 at z = 0; 60 × 50
  // exact points over its heights 0.05-0.95, every normal straight up (the tangent planes then
  // meet in no point: estimateCone's apex is degenerate).
  const Eigen::Vector3d apex(1, 1, 1);
  const double half = std::atan(0.45);
  Eigen::Matrix3Xd points(3, 3000), normals(3, 3000);
  for (int a = 0; a < 60; ++a)
    for (int h = 0; h < 50; ++h) {
      const double angle = 2 * M_PI * a / 60, depth = 0.05 + 0.9 * h / 49;
      const double rho = depth * std::tan(half);
      points.col(a * 50 + h) =
          apex + Eigen::Vector3d(rho * std::cos(angle), rho * std::sin(angle), -depth);
      normals.col(a * 50 + h) = Eigen::Vector3d::UnitZ();
    }
  const Eigen::VectorXd weights = Eigen::VectorXd::Ones(3000);
  EXPECT_FALSE(refitJoined(PrimitiveType::cone, points, normals, weights, std::nullopt).ok());
  // A piece's fit 2° and 0.02 off.
  const Cone piece{Eigen::Vector3d(std::sin(2 * M_PI / 180), 0, -std::cos(2 * M_PI / 180)),
                   apex + Eigen::Vector3d(0.02, -0.01, 0.01), half + 0.03};
  const FitResult fit = refitJoined(PrimitiveType::cone, points, normals, weights, piece);
  ASSERT_TRUE(fit.ok()) << fit.reason;
  const Cone& cone = std::get<Cone>(fit.refined);
  EXPECT_LT((cone.apex - apex).norm(), 1e-6);
  EXPECT_GT(std::abs(cone.axis.normalized().z()), std::cos(1e-6));
  EXPECT_NEAR(cone.half_angle, half, 1e-6);
  // A cylinder's fit is no start for a cone.
  const Cylinder other{Eigen::Vector3d::UnitZ(), apex, 0.3};
  EXPECT_FALSE(refitJoined(PrimitiveType::cone, points, normals, weights, other).ok());
}

}  // namespace
}  // namespace slipfit::pipeline::tiling
