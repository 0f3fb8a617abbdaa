#pragma once
/// \file Sorting many doubles in linear time: an LSD radix sort on their bits, mapped to unsigned
/// keys that order as the values do. The lattice detection (depth_quantization.cpp) sorts every
/// coordinate of a cloud up to three times a run; std::sort of a million doubles took 0.07 s
/// an axis, this a fifth of it.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace slipfit {

namespace detail {
/// The key of \a v: its bits with the sign bit flipped (non-negative values), or all bits flipped
/// (negative ones), so that keys order as values do; −0 and +0 get the key of +0.
inline std::uint64_t orderedKey(double v) {
  if (v == 0.0)
    v = 0.0;
  std::uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  return (bits >> 63) != 0 ? ~bits : bits | (std::uint64_t{1} << 63);
}
inline double valueOfKey(std::uint64_t key) {
  const std::uint64_t bits = (key >> 63) != 0 ? key & ~(std::uint64_t{1} << 63) : ~key;
  double v;
  std::memcpy(&v, &bits, sizeof v);
  return v;
}
}  // namespace detail

/// Sorts \a values ascending, as std::sort does (−0 becomes +0). \a values must hold no NaN.
/// Small inputs go to std::sort; large ones take eight passes of one byte each, skipping a byte
/// that all keys share (the exponent bytes of coordinates of one scale).
inline void radixSort(std::vector<double>& values) {
  constexpr std::size_t kSmall = 4096;
  if (values.size() < kSmall) {
    std::sort(values.begin(), values.end());
    for (double& v : values)
      v = v == 0.0 ? 0.0 : v;
    return;
  }
  std::vector<std::uint64_t> keys(values.size()), other(values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    keys[i] = detail::orderedKey(values[i]);
  for (int shift = 0; shift < 64; shift += 8) {
    std::array<std::size_t, 257> start{};
    for (const std::uint64_t k : keys)
      ++start[((k >> shift) & 0xff) + 1];
    if (std::find(start.begin() + 1, start.end(), keys.size()) != start.end())
      continue;  // one bucket holds every key: this byte orders nothing
    for (std::size_t b = 1; b < start.size(); ++b)
      start[b] += start[b - 1];
    for (const std::uint64_t k : keys)
      other[start[(k >> shift) & 0xff]++] = k;
    keys.swap(other);
  }
  for (std::size_t i = 0; i < values.size(); ++i)
    values[i] = detail::valueOfKey(keys[i]);
}

}  // namespace slipfit
