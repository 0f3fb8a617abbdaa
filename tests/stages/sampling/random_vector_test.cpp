// randomVector: N draws of a distribution, coordinate N − 1 first, whatever the compiler.
#include "slipfit/sampling/random_vector.h"

#include <gtest/gtest.h>

#include <random>

namespace slipfit {
namespace {

TEST(RandomVector, DrawsTheLastCoordinateFirst) {
  std::mt19937_64 a(5), b(5);
  std::normal_distribution<double> ga(0.0, 1.0), gb(0.0, 1.0);
  const Eigen::Vector3d v = randomVector<3>(ga, a);
  const double first = gb(b), second = gb(b), third = gb(b);
  EXPECT_EQ(v.z(), first);
  EXPECT_EQ(v.y(), second);
  EXPECT_EQ(v.x(), third);
  // The engines are at the same place: the next draws agree.
  EXPECT_EQ(ga(a), gb(b));
}

TEST(RandomVector, KeepsTheDistributionsScalarAndSize) {
  std::mt19937 a(9), b(9);
  std::uniform_real_distribution<float> ua(-1.0f, 1.0f), ub(-1.0f, 1.0f);
  const Eigen::Matrix<float, 4, 1> v = randomVector<4>(ua, a);
  for (int i = 3; i >= 0; --i)
    EXPECT_EQ(v(i), ub(b)) << "coordinate " << i;
}

}  // namespace
}  // namespace slipfit
