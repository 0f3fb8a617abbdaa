// Walls about as thick as the spacing: every neighborhood of a dozen points holds both faces.
// Fit4CAD holds such parts (PC13, a plate one spacing thick; PC184, a conical shell 1.4 spacings
// thick); before the sheets were told apart, PC13's noise read as 0.7 units on noise-free data and
// one plane took both faces, and PC184's two cones were left unassigned.

#include "points_cloud.h"
#include "segment_cloud.h"
#include "slipfit/sampling/random_vector.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>

namespace slipfit {
namespace {

struct Shell {
  Eigen::Matrix3Xd points;
  std::vector<int> sheet;  ///< 0 or 1: which face a point lies on
};

/// Two parallel faces of a plate \a thickness thick, 40 × 20, 1,500 random points each: median
/// nearest-neighbour distance within a face 0.47 / √(1500 / 800) ≈ 0.34.
Shell plate(double thickness, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> x(0.0, 40.0), y(0.0, 20.0);
  Shell s;
  s.points.resize(3, 3000);
  for (int i = 0; i < 3000; ++i) {
    s.sheet.push_back(i % 2);
    s.points.col(i) << x(rng), y(rng), (i % 2) * thickness;
  }
  return s;
}

/// Two coaxial cones of half-angle 14° (axis z, opening upward) whose surfaces lie \a thickness
/// apart along their normals, between heights 0 and 20. Random: 6,000 points each, uniform in
/// area (median nearest-neighbour distance 0.19). Meshed: rings 0.2 apart along the slant, points
/// 0.2 apart along each ring, and each point of the outer cone has its twin on the inner cone
/// \a thickness away along the normal, as a CAD part tessellated face by face is sampled.
Shell conicalShell(double thickness, bool meshed, unsigned seed) {
  constexpr double kHalfAngle = 14.0 * M_PI / 180.0;
  constexpr double kTop = 20.0;
  constexpr double kApexDepth = 20.0;  // the outer cone's apex lies this far below height 0
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  Shell s;
  auto add = [&](double t, double phi) {  // t: height above the outer apex
    const double r = t * std::tan(kHalfAngle);
    const Eigen::Vector3d outer(r * std::cos(phi), r * std::sin(phi), t - kApexDepth);
    const Eigen::Vector3d normal(std::cos(kHalfAngle) * std::cos(phi),
                                 std::cos(kHalfAngle) * std::sin(phi), -std::sin(kHalfAngle));
    points.push_back(outer);
    s.sheet.push_back(0);
    points.push_back(outer - thickness * normal);
    s.sheet.push_back(1);
  };
  if (meshed) {
    constexpr double kStep = 0.2;
    const double slant_step = kStep * std::cos(kHalfAngle);  // in height
    for (double t = kApexDepth; t <= kApexDepth + kTop; t += slant_step) {
      const int around = static_cast<int>(2.0 * M_PI * t * std::tan(kHalfAngle) / kStep);
      for (int j = 0; j < around; ++j)
        add(t, 2.0 * M_PI * j / around);
    }
  } else {
    const double t0 = kApexDepth, t1 = kApexDepth + kTop;
    for (int i = 0; i < 6000; ++i) {
      const Eigen::Vector2d w = randomVector<2>(u, rng);
      add(std::sqrt(t0 * t0 + w(0) * (t1 * t1 - t0 * t0)), 2.0 * M_PI * w(1));
    }
  }
  // Tilted: rings at regular heights along a coordinate axis would read as depth levels.
  const Eigen::Matrix3d tilt =
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(1.0, 1.0, 0.0).normalized()).toRotationMatrix();
  s.points.resize(3, static_cast<Eigen::Index>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i)
    s.points.col(static_cast<Eigen::Index>(i)) = tilt * points[i];
  return s;
}

/// For each face, the largest share of its points in one segment of \a type that holds at most
/// 1 % of the other face's points; 0 when no segment does.
std::array<double, 2> facesFound(const Shell& s, const SegmentationResult& r, PrimitiveType type) {
  std::array<double, 2> best{0.0, 0.0};
  const double per_sheet = static_cast<double>(s.sheet.size()) / 2.0;
  for (const Segment& segment : r.segments) {
    if (segment.fit.type != type)
      continue;
    std::array<double, 2> count{0.0, 0.0};
    for (int i : segment.indices)
      count[static_cast<std::size_t>(s.sheet[static_cast<std::size_t>(i)])] += 1.0;
    for (std::size_t f = 0; f < 2; ++f)
      if (count[1 - f] <= 0.01 * per_sheet)
        best[f] = std::max(best[f], count[f] / per_sheet);
  }
  return best;
}

// A noise-free plate 0.24 thick, 0.7 of the spacing within a face (PC13's: 1.0 and 0.99): the
// noise estimate fits each point's own face
// (0; mixing both faces it read 0.14, more than half the thickness, and one plane took both
// faces), and each face is a plane. Measured on seeds 1–3: σ̂ = 0, each face 0.991–0.997 in one
// plane.
TEST(ThinWall, APlateAsThickAsItsSpacingIsTwoPlanes) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const Shell s = plate(0.24, seed);
    const testing::SegmentedCloud out = testing::segmentCloud(testing::pointsCloud(s.points), 12);
    EXPECT_LT(out.result.noise, 1e-6) << "seed " << seed;
    const std::array<double, 2> found = facesFound(s, out.result, PrimitiveType::plane);
    EXPECT_GE(found[0], 0.991) << "seed " << seed;
    EXPECT_GE(found[1], 0.991) << "seed " << seed;
  }
}

// A noise-free conical shell 1.4 spacings thick (PC184's): every neighborhood holds both cones.
// Sampled at random, the noise estimate on each point's own sheet is what needs mending; meshed,
// with twin points on the two cones, no local slippage agrees and no free seed's neighbors fit a
// primitive, but the seed's own sheet of its 2-ring does (growFreeSeeds). Measured: each cone
// 0.925–0.959 in one cone segment at random (seeds 1–3; 0.06–0.48 without the seed's sheet, none
// without the noise on each point's own sheet), 0.972 / 0.974 meshed (0.81 / 0.83 without the
// seed's sheet).
void expectTwoCones(bool meshed, unsigned seed, double least) {
  const Shell s = conicalShell(meshed ? 0.28 : 0.27, meshed, seed);
  const testing::SegmentedCloud out = testing::segmentCloud(testing::pointsCloud(s.points), 12);
  const std::array<double, 2> found = facesFound(s, out.result, PrimitiveType::cone);
  const char* kind = meshed ? "meshed" : "random";
  std::cout << kind << " seed " << seed << ": noise " << out.result.noise << ", distance "
            << out.result.distance << ", " << out.result.segments.size() << " segments, faces "
            << found[0] << " / " << found[1] << "\n";
  EXPECT_GE(found[0], least) << kind << " seed " << seed;
  EXPECT_GE(found[1], least) << kind << " seed " << seed;
}

TEST(ThinWall, AConicalShellThickerThanItsSpacingIsTwoCones) {
  for (unsigned seed : {1u, 2u, 3u})
    expectTwoCones(false, seed, 0.925);
}

// The meshed shell has no randomness: one run (the one the sanitizer job makes of this case).
TEST(ThinWall, AMeshedConicalShellIsTwoCones) {
  expectTwoCones(true, 1u, 0.971);
}

}  // namespace
}  // namespace slipfit
