// A fillet between two planes at the noise where the planes take it whole as they grow: radius
// 20 σ, so that all but its middle rows lie within the planes' tolerance (3 σ and a little) and
// the middle ones only r (1 − sin 45°) ≈ 5.9 σ off both (random 1 M-point scenes, seed 61: a
// bracket's fillet of 32,418 points went to its two planes).

#include "points_cloud.h"
#include "segment_cloud.h"

#include "slipfit/sampling/random_vector.h"
#include "slipfit/segmentation/crease_fillet.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>

namespace slipfit {
namespace {

constexpr double kRadius = 0.04;
constexpr double kSigma = 0.002;
constexpr double kLength = 1.0;  // along the crease
constexpr double kWidth = 0.3;   // each plane's, across it
// Points per unit area: a median spacing of 0.47 / √6000 ≈ 3 σ, as the 1 M-point scenes' voxel
// subsample has it (spacing 0.013 at σ 0.002 and more).
constexpr double kDensity = 6000.0;

struct Bracket {
  Eigen::Matrix3Xd points;
  std::vector<int> part;  ///< 0, 1: the planes; 2: the fillet
};

/// Planes z = 0 (y ≥ r) and y = 0 (z ≥ r) joined by a quarter cylinder of radius r about the
/// line y = z = r, kDensity points per unit area, Gaussian noise σ along the normal.
Bracket bracket(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, kSigma);
  std::vector<Eigen::Vector3d> p;
  Bracket b;
  const int planar = static_cast<int>(kDensity * kLength * kWidth);
  for (int i = 0; i < planar; ++i) {
    // Drawn z, y, x (randomVector's order).
    double z = noise(rng), y = kRadius + kWidth * u(rng);
    p.emplace_back(kLength * u(rng), y, z);
    b.part.push_back(0);
    z = kRadius + kWidth * u(rng);
    y = noise(rng);
    p.emplace_back(kLength * u(rng), y, z);
    b.part.push_back(1);
  }
  const int curved = static_cast<int>(kDensity * kLength * 0.5 * M_PI * kRadius);
  for (int i = 0; i < curved; ++i) {
    const double phi = M_PI + 0.5 * M_PI * u(rng);
    const double r = kRadius + noise(rng);
    p.emplace_back(kLength * u(rng), kRadius + r * std::cos(phi), kRadius + r * std::sin(phi));
    b.part.push_back(2);
  }
  b.points.resize(3, static_cast<Eigen::Index>(p.size()));
  for (std::size_t i = 0; i < p.size(); ++i)
    b.points.col(static_cast<Eigen::Index>(i)) = p[i];
  return b;
}

// The model: the rounded crease's distance is the planes' beyond the tangent points and the
// arc's between them, and on noise-free points of the bracket the fitted radius is the true one.
TEST(CreaseFillet, TheRadiusOfANoiseFreeFilletIsRecovered) {
  Bracket b = bracket(1);
  // Noise-free copy: project each point onto its part.
  for (Eigen::Index i = 0; i < b.points.cols(); ++i) {
    Eigen::Ref<Eigen::Vector3d> q = b.points.col(i);
    switch (b.part[static_cast<std::size_t>(i)]) {
      case 0:
        q.z() = 0.0;
        break;
      case 1:
        q.y() = 0.0;
        break;
      default: {
        const Eigen::Vector2d v = Eigen::Vector2d(q.y(), q.z()) - Eigen::Vector2d(kRadius, kRadius);
        const Eigen::Vector2d on = Eigen::Vector2d(kRadius, kRadius) + kRadius * v.normalized();
        q.y() = on.x();
        q.z() = on.y();
      }
    }
  }
  Plane za, yb;
  za.normal = Eigen::Vector3d::UnitZ();
  yb.normal = Eigen::Vector3d::UnitY();
  std::vector<int> a, c;
  for (std::size_t i = 0; i < b.part.size(); ++i)
    (b.part[i] == 1 ? c : a).push_back(static_cast<int>(i));
  const std::optional<CreaseSection> s =
      creaseSection(za, yb, b.points(Eigen::all, a), b.points(Eigen::all, c));
  ASSERT_TRUE(s);
  EXPECT_NEAR(s->opening, 0.5 * M_PI, 1e-12);
  double d = 0.0;
  // A point on the arc's middle: distance 0 at the true radius, r (√2 − 1) to the sharp crease.
  const Eigen::Vector3d middle(0.1, kRadius * (1.0 - std::sqrt(0.5)),
                               kRadius * (1.0 - std::sqrt(0.5)));
  EXPECT_EQ(filletDistance(*s, kRadius, middle, &d), FilletPiece::arc);
  EXPECT_NEAR(d, 0.0, 1e-12);
  filletDistance(*s, 0.0, middle, &d);
  EXPECT_NEAR(d, kRadius * (1.0 - std::sqrt(0.5)), 1e-12);
  const Eigen::VectorXd sigma = Eigen::VectorXd::Constant(b.points.cols(), kSigma);
  const FilletChoice choice = chooseFilletRadius(*s, b.points, sigma, 0.001, 0.1);
  EXPECT_NEAR(choice.radius, kRadius, 1e-3 * kRadius);
  EXPECT_GT(choice.sharp_cost, choice.cost);
}

// End to end at σ = r / 20: the fillet is one cylinder near the true radius, the planes keep most
// of their points. Measured on seeds 1–3: the cylinder holds 0.907 / 0.979 / 0.955 of the fillet's
// points, 0.789 / 0.811 / 0.831 of its own points are the fillet's (the rest lie on the planes by
// the tangent lines, within the noise of both), radius 0.0384 / 0.0389 / 0.0369 (r = 0.04: the
// plane points it holds pull it in). Without recoverFillets the planes took the fillet's edges and
// the best cylinder held 0.649 / 0.309 / 0.176 of it.
TEST(CreaseFillet, AFilletOfTwentySigmaBetweenTwoPlanesIsACylinder) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const Bracket b = bracket(seed);
    const testing::SegmentedCloud out = testing::segmentCloud(testing::pointsCloud(b.points), 12);
    std::size_t fillet_points = 0;
    for (int part : b.part)
      fillet_points += part == 2 ? 1 : 0;
    double best_share = 0.0, radius = 0.0, precision = 0.0;
    for (const Segment& segment : out.result.segments) {
      const auto* cylinder = std::get_if<Cylinder>(&segment.fit.refined);
      if (!cylinder)
        continue;
      std::size_t on = 0;
      for (int i : segment.indices)
        on += b.part[static_cast<std::size_t>(i)] == 2 ? 1 : 0;
      const double share = static_cast<double>(on) / static_cast<double>(fillet_points);
      if (share > best_share) {
        best_share = share;
        radius = cylinder->radius;
        precision = static_cast<double>(on) / static_cast<double>(segment.indices.size());
      }
    }
    std::cout << "seed " << seed << ": " << out.result.segments.size() << " segments, "
              << out.result.fillets << " fillets, fillet share " << best_share << ", precision "
              << precision << ", radius " << radius << "\n";
    EXPECT_GE(best_share, 0.906) << "seed " << seed;
    EXPECT_GE(precision, 0.789) << "seed " << seed;
    EXPECT_NEAR(radius, kRadius, 0.077 * kRadius) << "seed " << seed;
  }
}

// The switch of phase 6 (SegmentationParameters::fillets): off, no fillet is recovered and the
// planes keep the fillet's edges: no cylinder holds two thirds of it on seeds 1-3 (0.65, 0.31 and
// 0.18), against 0.906 or more with it on (above).
TEST(CreaseFillet, WithFilletsOffTheCreaseStaysSharp) {
  SegmentationParameters parameters;
  parameters.fillets = false;
  for (const unsigned seed : {1u, 2u, 3u}) {
    const double most = 2.0 / 3.0;
    const Bracket b = bracket(seed);
    const testing::SegmentedCloud out =
        testing::segmentCloud(testing::pointsCloud(b.points), 12, nullptr, parameters);
    EXPECT_EQ(out.result.fillets, 0u) << "seed " << seed;
    std::size_t fillet_points = 0;
    for (int part : b.part)
      fillet_points += part == 2 ? 1 : 0;
    double best_share = 0.0;
    for (const Segment& segment : out.result.segments) {
      if (!std::holds_alternative<Cylinder>(segment.fit.refined))
        continue;
      std::size_t on = 0;
      for (int i : segment.indices)
        on += b.part[static_cast<std::size_t>(i)] == 2 ? 1 : 0;
      best_share = std::max(best_share, static_cast<double>(on) / fillet_points);
    }
    std::cout << "seed " << seed << ", fillets off: best cylinder share " << best_share << "\n";
    EXPECT_LE(best_share, most) << "seed " << seed;
  }
}

}  // namespace
}  // namespace slipfit
