// The kinematic scene: every sample on its true surface with that surface's normal, uniform in
// area within each surface, the noise at the σ asked for, and the same bytes for the same seed.

#include "slipfit/core/exceptions.h"
#include "slipfit/sampling/kinematic_sampler.h"
#include "slipfit/sampling/kinematic_scene_sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <variant>

namespace slipfit {
namespace {

double distanceTo(const SurfaceTruth& truth, const Eigen::Vector3d& p) {
  if (const auto* primitive = std::get_if<Primitive>(&truth))
    return distance(p, *primitive);
  return distance(p, std::get<KinematicSurface>(truth));
}

/// Whether \a x projects onto \a s's profile within \a reach of a vertex of it, where a step
/// along the normal may come nearer the next segment.
bool nearAVertex(const SurfaceTruth& truth, const Eigen::Vector3d& x, double reach) {
  const auto* s = std::get_if<KinematicSurface>(&truth);
  if (!s)
    return false;
  const ProfileProjection p = projectOnProfile(*s, x);
  const auto& v = s->profile.vertices;
  const double length = (v[(p.segment + 1) % v.size()] - v[p.segment]).norm();
  return std::min(p.t, 1.0 - p.t) * length < reach;
}

// Clean samples lie on their surface (the kinematic ones on the polyline surface they were drawn
// from) to rounding, and a step of δ = 10⁻³ along the normal is δ away: exactly on the
// primitives, revolutions and extrusions, to first order on the thread (the helical metric), off
// by at most 10 % there. Samples within 2 δ of a profile vertex are left out of the step: near a
// concave corner (the thread's 54° ones) the next segment is nearer.
TEST(KinematicScene, SamplesAreOnTheirTruthWithItsNormal) {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    KinematicSceneParameters p;
    p.points = 30000;
    p.seed = seed;
    const KinematicScene scene = sampleKinematicScene(p);
    ASSERT_EQ(scene.truth.size(), 10u);  // plate; turned part + top; extrusion + top; rod + top;
                                         // cylinder + top; sphere
    ASSERT_EQ(scene.labels.size(), 30000u);
    int kinematic = 0;
    for (const SurfaceTruth& t : scene.truth)
      kinematic += std::holds_alternative<KinematicSurface>(t) ? 1 : 0;
    EXPECT_EQ(kinematic, 3);
    constexpr double kStep = 1e-3;
    for (Eigen::Index i = 0; i < scene.points.cols(); ++i) {
      const SurfaceTruth& t = scene.truth[static_cast<std::size_t>(scene.labels[i])];
      const Eigen::Vector3d x = scene.points.col(i), n = scene.normals.col(i);
      ASSERT_NEAR(n.norm(), 1.0, 1e-12);
      ASSERT_LE(distanceTo(t, x), 1e-12) << "seed " << seed << " point " << i;
      const std::int32_t type = truthTypeCode(t);
      if (nearAVertex(t, x, 2.0 * kStep))
        continue;
      const double tolerance = type == 7 ? 0.1 * kStep : 1e-9;
      ASSERT_NEAR(distanceTo(t, x + kStep * n), kStep, tolerance)
          << "seed " << seed << " point " << i << " type " << type;
    }
  }
}

/// The share of \a s's samples \a x whose first profile coordinate is below that of profile vertex
/// \a vertex against the share of the area there (the profile up to that vertex).
void expectAreaShare(const KinematicSurface& s, const MotionStretch& stretch, std::size_t vertex,
                     const Eigen::Matrix3Xd& x) {
  KinematicSurface head = s;
  head.profile.closed = false;
  head.profile.vertices.resize(vertex + 1);
  const double share = kinematicArea(head, stretch) / kinematicArea(s, stretch);
  const double cut = s.profile.vertices[vertex].x();
  int below = 0;
  for (Eigen::Index i = 0; i < x.cols(); ++i)
    below += profileCoordinates(s, x.col(i)).x() < cut ? 1 : 0;
  const double n = static_cast<double>(x.cols());
  // Binomial: 4 standard deviations.
  EXPECT_NEAR(below / n, share, 4.0 * std::sqrt(share * (1.0 - share) / n))
      << kinematicTypeName(s.type);
}

// Uniform in area: the samples of a revolution below a height, and of a thread on the root side
// of a flank's top (its area element √(ρ² + ρ'² pitch²) grows along the flank), come in the share
// of the area there, within 4 binomial standard deviations of 20,000 samples.
TEST(KinematicScene, KinematicSamplesAreUniformInArea) {
  std::mt19937_64 rng(5);
  KinematicSurface vase;
  vase.type = KinematicType::revolution;
  for (int i = 0; i <= 40; ++i)
    vase.profile.vertices.emplace_back(0.05 * i, 0.2 + 0.8 * i / 40.0);  // a cone band, ρ 0.2–1
  Eigen::Matrix3Xd x, n;
  sampleKinematicSurface(vase, {0.0, 2.0 * M_PI}, 20000, rng, x, n);
  expectAreaShare(vase, {0.0, 2.0 * M_PI}, 20, x);

  KinematicSurface thread;
  thread.type = KinematicType::helix;
  thread.pitch = 0.05;
  const double period = 2.0 * M_PI * thread.pitch;
  for (const auto& [u, rho] : {std::pair{0.0, 0.1}, {0.5, 0.6}, {1.0, 0.1}})
    thread.profile.vertices.emplace_back(u * period, rho);
  sampleKinematicSurface(thread, {0.0, 1.0}, 20000, rng, x, n);
  // The rising flank: half of the profile's arc and of its area (the profile is symmetric).
  expectAreaShare(thread, {0.0, 1.0}, 1, x);
  // A thread whose flanks differ: the steep one (ρ' large) has the larger area element.
  thread.profile.vertices = {{0.0, 0.1}, {0.2 * period, 0.6}, {period, 0.1}};
  sampleKinematicSurface(thread, {0.0, 1.0}, 20000, rng, x, n);
  expectAreaShare(thread, {0.0, 1.0}, 1, x);
}

// Noise σ = 1 % of the median part size: the RMS distance to the truth is σ (isotropic noise,
// its component along the normal), within 5 % (the curvature of the thread's flanks and crests
// bends a few percent of it).
TEST(KinematicScene, NoiseIsTheFractionOfTheMedianSize) {
  KinematicSceneParameters p;
  p.points = 20000;
  p.noise = 0.01;
  p.seed = 4;
  const KinematicScene scene = sampleKinematicScene(p);
  const double sigma = 0.01 * scene.median_size;
  EXPECT_GT(scene.median_size, 0.3);
  EXPECT_LT(scene.median_size, 0.9);
  double sum = 0.0;
  for (Eigen::Index i = 0; i < scene.points.cols(); ++i) {
    const double d =
        distanceTo(scene.truth[static_cast<std::size_t>(scene.labels[i])], scene.points.col(i));
    sum += d * d;
  }
  EXPECT_NEAR(std::sqrt(sum / scene.points.cols()), sigma, 0.05 * sigma);
}

TEST(KinematicScene, TheSeedGivesTheSceneAndBadParametersAreRefused) {
  KinematicSceneParameters p;
  p.points = 2000;
  p.seed = 11;
  const KinematicScene a = sampleKinematicScene(p), b = sampleKinematicScene(p);
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.labels, b.labels);
  p.seed = 12;
  EXPECT_NE(sampleKinematicScene(p).points, a.points);
  p.primitives = false;
  const KinematicScene bare = sampleKinematicScene(p);
  EXPECT_EQ(bare.truth.size(), 7u);
  EXPECT_EQ(truthTypeCode(bare.truth[0]), 0);  // the plate
  p.points = 99;
  EXPECT_THROW(sampleKinematicScene(p), InvalidParameterError);
  p.points = 1000;
  p.noise = 0.06;
  EXPECT_THROW(sampleKinematicScene(p), InvalidParameterError);
}

}  // namespace
}  // namespace slipfit
