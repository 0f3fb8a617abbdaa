// Classification accuracy of whole-cloud slippage on seeded random clouds (plane, sphere,
// cylinder, cone) in random poses and scales, with noise, partial coverage and flipped normals:
// the spectrum's own reading (analyzeSlippage, as each neighbourhood gets it) and the whole-cloud
// verdict (classifyShape). Prints the confusion matrix of each.
#include "varied_shapes.h"

#include "slipfit/core/angle_units.h"
#include "slipfit/sampling/primitive_sampler.h"
#include "slipfit/sampling/random_vector.h"
#include "slipfit/slippage/shape_classification.h"
#include "slipfit/slippage/slippage.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <map>
#include <random>

namespace slipfit {
namespace {

struct Trial {
  SlippageType truth;
  Eigen::Matrix3Xd x, n;
};

/// Cloud number \a i of a seeded family: type i % 4, random pose, size from {1e-3, 1, 1e3},
/// every third one 1e4 from the origin, partial coverage on odd ones, 30 % flipped normals.
Trial makeTrial(int i, double noise_fraction, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), unit(0.0, 1.0);
  const double sizes[] = {1e-3, 1.0, 1e3};
  const double size = sizes[i % 3];
  const Eigen::Vector3d axis = randomVector<3>(u, rng).normalized();
  const Eigen::Vector3d where =
      (i % 3 == 1 ? 1e4 : 0.0) * Eigen::Vector3d::Ones() + size * randomVector<3>(u, rng);
  PrimitiveSamplingParameters p;
  p.points = 2000;
  p.seed = 1000 + static_cast<std::uint64_t>(i);
  p.flip_fraction = 0.3;
  p.noise = noise_fraction * size;
  const bool partial = i % 2 == 1;
  Trial t;
  switch (i % 4) {
    case 0:
      p.primitive = Plane{axis, axis.dot(where)};
      p.extent = size;
      t.truth = SlippageType::plane;
      break;
    case 1:
      p.primitive = Sphere{where, size};
      p.cap = partial ? 70 * kDegree : kPi;
      p.axis_hint = axis.unitOrthogonal();
      t.truth = SlippageType::sphere;
      break;
    case 2:
      p.primitive = Cylinder{axis, where, 0.5 * size};
      p.extent = 2 * size;
      p.angle_max = partial ? 150 * kDegree : 2 * kPi;
      t.truth = SlippageType::cylinder;
      break;
    default:
      p.primitive = Cone{axis, where, (20 + 30 * unit(rng)) * kDegree};
      p.extent_min = 0.3 * size;
      p.extent = 1.3 * size;
      p.angle_max = partial ? 200 * kDegree : 2 * kPi;
      t.truth = SlippageType::cone;
      break;
  }
  samplePrimitive(p, t.x, t.n);
  return t;
}

/// Runs \a count trials; returns the number right and prints the confusion matrix.
int accuracy(int count, double noise, bool estimated_normals, bool whole, const char* title) {
  std::mt19937_64 rng(20041);
  std::map<SlippageType, std::map<SlippageType, int>> confusion;
  int right = 0;
  for (int i = 0; i < count; ++i) {
    Trial t = makeTrial(i, noise, rng);
    if (estimated_normals)
      testing::estimatePcaNormals(t.x, 24, t.n);
    const Eigen::VectorXd w = Eigen::VectorXd::Ones(t.x.cols());
    const SlippageResult r =
        whole ? classifyShape(t.x, t.n, w).verdict : analyzeSlippage(t.x, t.n, w);
    ++confusion[t.truth][r.type];
    if (r.type != t.truth && std::getenv("SLIPPAGE_DEBUG"))
      std::cout << "trial " << i << " " << slippageTypeName(t.truth) << " -> "
                << slippageTypeName(r.type) << " k=" << r.motions << " spectrum "
                << r.spectrum.transpose() << " " << r.reason << "\n";
    right += r.type == t.truth ? 1 : 0;
  }
  std::cout << title << ": " << right << "/" << count << " right\n"
            << std::setw(12) << "truth \\ got";
  for (const auto& [type, name] : kSlippageTypeNames)
    std::cout << std::setw(11) << name;
  std::cout << "\n";
  for (const auto& [truth, row] : confusion) {
    std::cout << std::setw(12) << slippageTypeName(truth);
    for (const auto& [type, name] : kSlippageTypeNames)
      std::cout << std::setw(11) << (row.count(type) ? row.at(type) : 0);
    std::cout << "\n";
  }
  return right;
}

TEST(SlippageAccuracy, ExactNormalsUpToOnePercentNoise) {
  for (const bool whole : {false, true})
    for (const double noise : {0.0, 0.005, 0.01}) {
      const std::string title = std::string(whole ? "whole-cloud verdict" : "spectrum") +
                                ", exact normals, noise " + std::to_string(noise * 100) + " %";
      EXPECT_EQ(accuracy(200, noise, false, whole, title.c_str()), 200) << title;
    }
}

TEST(SlippageAccuracy, EstimatedNormalsAtTwoPercentNoise) {
  // The spectrum alone: 188 of 200 (the partial cones with noisy normals show some pitch and
  // read as helices); the whole-cloud verdict, which lets the positions decide: all 200.
  EXPECT_GE(accuracy(200, 0.02, true, false, "spectrum, estimated normals (k = 24), noise 2 %"),
            188);
  EXPECT_EQ(
      accuracy(200, 0.02, true, true, "whole-cloud verdict, estimated normals (k = 24), noise 2 %"),
      200);
}

}  // namespace
}  // namespace slipfit
