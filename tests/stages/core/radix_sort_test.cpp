// radixSort (core/radix_sort.h) against std::sort: the same sequence, bit for bit, for values of
// every sign and scale, many equal ones, infinities and subnormals, below and above the size at
// which it leaves the work to std::sort; −0 comes out as +0.
#include "slipfit/core/radix_sort.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace slipfit {
namespace {

/// The bits of each value: equal sequences of doubles, +0 and −0 told apart.
std::vector<std::uint64_t> bitsOf(const std::vector<double>& v) {
  std::vector<std::uint64_t> b(v.size());
  for (std::size_t i = 0; i < v.size(); ++i)
    std::memcpy(&b[i], &v[i], sizeof(double));
  return b;
}

void expectSortedAsStdSort(std::vector<double> values) {
  std::vector<double> expected = values;
  std::sort(expected.begin(), expected.end());
  for (double& v : expected)
    v = v == 0.0 ? 0.0 : v;  // −0 and +0 are equal to std::sort; radixSort writes +0
  radixSort(values);
  EXPECT_EQ(bitsOf(values), bitsOf(expected));
}

TEST(RadixSort, SortsAsStdSortDoesAtEverySizeSignAndScale) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_int_distribution<int> exponent(-300, 300), level(-40, 40);
  for (const std::size_t n : {0u, 1u, 100u, 4095u, 4096u, 100000u}) {
    std::vector<double> wide(n), levels(n), coordinates(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double mantissa = normal(rng);
      wide[i] = mantissa * std::pow(10.0, exponent(rng));
      levels[i] = 0.0125 * level(rng);            // a depth lattice: every value many times
      coordinates[i] = 2.5 + 0.01 * normal(rng);  // one scale: its exponent bytes all alike
    }
    expectSortedAsStdSort(wide);
    expectSortedAsStdSort(levels);
    expectSortedAsStdSort(coordinates);
  }
  std::vector<double> special = {0.0,
                                 -0.0,
                                 std::numeric_limits<double>::infinity(),
                                 -std::numeric_limits<double>::infinity(),
                                 std::numeric_limits<double>::denorm_min(),
                                 -std::numeric_limits<double>::denorm_min(),
                                 std::numeric_limits<double>::max(),
                                 std::numeric_limits<double>::lowest(),
                                 1.0,
                                 -1.0};
  std::vector<double> many;
  for (int copy = 0; copy < 1000; ++copy)
    many.insert(many.end(), special.begin(), special.end());
  expectSortedAsStdSort(special);
  expectSortedAsStdSort(many);
}

}  // namespace
}  // namespace slipfit
