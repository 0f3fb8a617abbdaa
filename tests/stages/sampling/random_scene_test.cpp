// The random scene generator: every surface sample lies on the primitive of its label, every
// shape has its 500–50,000 points, the types and the fillets come out as specified, and the
// scene is the same for the same seed.
#include "slipfit/core/exceptions.h"
#include "slipfit/sampling/random_scene_sampler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace slipfit {
namespace {

TEST(RandomScene, SamplesLieOnTheirPrimitives) {
  RandomSceneParameters p;
  p.shapes = 60;
  p.points = 200000;
  p.seed = 3;
  Eigen::Matrix3Xd x, n;
  std::vector<std::int32_t> labels;
  std::vector<Primitive> truth;
  sampleRandomScene(p, x, n, labels, truth);
  ASSERT_EQ(truth.size(), 60u);
  ASSERT_EQ(labels.size(), static_cast<std::size_t>(x.cols()));
  std::map<int, std::size_t> count;
  std::map<PrimitiveType, int> types;
  double worst = 0.0, worst_normal = 0.0;
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    const int l = labels[static_cast<std::size_t>(i)];
    ASSERT_GE(l, 0);
    ++count[l];
    const Primitive& s = truth[static_cast<std::size_t>(l)];
    // Coordinates up to ~100 units: 1e-12 relative rounding, far below 1e-9.
    worst = std::max(worst, distance(x.col(i), s));
    worst_normal = std::max(worst_normal, 1.0 - std::abs(surfaceNormal(x.col(i), s).dot(n.col(i))));
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(worst_normal, 1e-9);
  for (const auto& [label, c] : count) {
    EXPECT_GE(c, 500u) << label;
    EXPECT_LE(c, 50000u) << label;
    ++types[typeOf(truth[static_cast<std::size_t>(label)])];
  }
  EXPECT_EQ(count.size(), 60u);
  for (const PrimitiveType t : {PrimitiveType::plane, PrimitiveType::sphere,
                                PrimitiveType::cylinder, PrimitiveType::cone, PrimitiveType::torus})
    EXPECT_GT(types[t], 0) << primitiveTypeName(t);
}

TEST(RandomScene, SameSeedSameSceneAndOutliersOnTop) {
  RandomSceneParameters p;
  p.shapes = 10;
  p.points = 20000;
  p.noise = 0.01;
  p.outlier_fraction = 0.1;
  p.seed = 8;
  Eigen::Matrix3Xd a, b, n;
  std::vector<std::int32_t> la, lb;
  std::vector<Primitive> ta, tb;
  sampleRandomScene(p, a, n, la, ta);
  sampleRandomScene(p, b, n, lb, tb);
  EXPECT_EQ(a, b);
  EXPECT_EQ(la, lb);
  const auto outliers = std::count(la.begin(), la.end(), -1);
  const auto surface = static_cast<long>(la.size()) - outliers;
  EXPECT_EQ(outliers, std::lround(0.1 * static_cast<double>(surface)));
  p.shapes = 0;
  EXPECT_THROW(p.validate(), InvalidParameterError);
}

}  // namespace
}  // namespace slipfit
