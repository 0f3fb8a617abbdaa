// The whole-cloud verdict (classifyShape) on families of varied single shapes
// (tests/support/varied_shapes.h): the type of the five primitives, and the class, axis (1°) and
// pitch (2 %) of one-motion surfaces. Developed on seed 1; the suite runs held-out seed 2 and
// asserts its measured figures (SLIPPAGE_SEED=N runs another seed against the targets:
// 97 % of the primitives, 95 % at 2 % noise with PCA normals, 90 % of the one-motion surfaces).
// Held-out seeds 2–5: 1594 of 1600 primitives (99.6 %), 197 of 200 at 2 % noise with PCA normals
// (98.5 %), 398 of 400 one-motion surfaces. SLIPPAGE_DEBUG=1 lists every miss.
#include "varied_shapes.h"

#include "slipfit/core/angle_units.h"
#include "slipfit/slippage/shape_classification.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <iostream>

namespace slipfit {
namespace {

using testing::Disturbance;
using testing::VariedShape;

bool debug() {
  return std::getenv("SLIPPAGE_DEBUG") != nullptr;
}

std::uint64_t seedFromEnvironment(std::uint64_t fallback) {
  const char* s = std::getenv("SLIPPAGE_SEED");
  return s ? std::strtoull(s, nullptr, 10) : fallback;
}

struct Tally {
  int right = 0, total = 0;
  double rate() const { return total ? static_cast<double>(right) / total : 0.0; }
};

SlippageResult analyze(const VariedShape& s) {
  const ShapeClassification c =
      classifyShape(s.points, s.normals, Eigen::VectorXd::Ones(s.points.cols()));
  if (debug() && c.verdict.type != s.truth) {
    std::cout << "  noise " << c.noise << " floor " << c.floor << "\n";
    for (const ShapeCandidate& k : c.candidates)
      std::cout << "    " << primitiveTypeName(k.type) << " fitted " << k.fitted << " rms " << k.rms
                << " energy " << k.energy << " / " << k.energy_bound << "\n";
  }
  return c.verdict;
}

void report(const SlippageResult& r, const VariedShape& s, int i) {
  if (debug())
    std::cout << "  miss " << i << ": " << s.description << " -> " << slippageTypeName(r.type)
              << " k=" << r.motions << " spectrum " << r.spectrum.transpose() << " " << r.reason
              << "\n";
}

/// Classifies \a count shapes made by \a make and counts those \a judge calls right.
template <typename Make, typename Judge>
Tally tally(const char* what, std::uint64_t seed, const Disturbance& d, int count, Make make,
            Judge judge) {
  Tally t;
  for (int i = 0; i < count; ++i) {
    const VariedShape s = make(i, seed, d);
    const SlippageResult r = analyze(s);
    ++t.total;
    if (judge(r, s))
      ++t.right;
    else
      report(r, s, i);
  }
  std::cout << what << " seed " << seed << " noise " << d.noise * 100 << "% "
            << (d.estimated_normals ? "PCA" : "exact") << ": " << t.right << "/" << t.total << "\n";
  return t;
}

/// The class right.
Tally primitives(std::uint64_t seed, const Disturbance& d, int count) {
  return tally("primitives", seed, d, count, testing::variedPrimitive,
               [](const SlippageResult& r, const VariedShape& s) { return r.type == s.truth; });
}

/// The class right, the axis within 1° and a screw's pitch within 2 %.
Tally motionSurfaces(std::uint64_t seed, const Disturbance& d, int count) {
  return tally("motion surfaces", seed, d, count, testing::variedMotionSurface,
               [](const SlippageResult& r, const VariedShape& s) {
                 bool ok = r.type == s.truth && r.axis &&
                           std::abs(r.axis->dot(s.axis)) >= std::cos(1 * kDegree);
                 if (ok && s.truth == SlippageType::helix)
                   ok = r.pitch && std::abs(std::abs(*r.pitch) - std::abs(s.pitch)) <=
                                       0.02 * std::abs(s.pitch);
                 return ok;
               });
}

constexpr std::uint64_t kHeldOutSeed = 2;

TEST(SlippageVaried, PrimitiveTypes) {
  const std::uint64_t seed = seedFromEnvironment(kHeldOutSeed);
  Tally all, worst;
  for (const bool pca : {false, true})
    for (const double noise : {0.0, 0.005, 0.01, 0.02}) {
      const Tally t = primitives(seed, {noise, pca, true}, 50);
      all.right += t.right;
      all.total += t.total;
      if (pca && noise == 0.02)
        worst = t;
    }
  std::cout << "all: " << all.right << "/" << all.total << "\n";
  if (seed == kHeldOutSeed) {
    // Measured: 398 of 400; the misses are a band of a cylinder 0.17 radii high at 2 % noise,
    // which neither positions nor normals tell from a sphere.
    EXPECT_GE(all.right, 398);
    EXPECT_GE(worst.right, 49);  // of 50 at 2 % noise with PCA normals
  } else {
    EXPECT_GE(all.rate(), 0.97);
  }
}

TEST(SlippageVaried, TwoPercentNoiseWithPcaNormalsOverFourHeldOutSeeds) {
  // The hardest setting on 200 clouds: seeds 2–5 give 49, 50, 50 and 48 of 50.
  Tally all;
  for (const std::uint64_t seed : {2, 3, 4, 5}) {
    const Tally t = primitives(seed, {0.02, true, true}, 50);
    all.right += t.right;
    all.total += t.total;
  }
  EXPECT_GE(all.right, 197);  // of 200: 98.5 % (the target: 95 %)
}

TEST(SlippageVaried, MotionSurfaces) {
  const std::uint64_t seed = seedFromEnvironment(kHeldOutSeed);
  const Tally clean = motionSurfaces(seed, {0.0, false, true}, 50);
  const Tally noisy = motionSurfaces(seed, {0.01, true, true}, 50);
  if (seed == kHeldOutSeed) {
    EXPECT_EQ(clean.right, 50);
    EXPECT_EQ(noisy.right, 50);  // 1 % noise, PCA normals
  } else {
    EXPECT_GE(clean.rate(), 0.9);
    EXPECT_GE(noisy.rate(), 0.9);
  }
}

}  // namespace
}  // namespace slipfit
