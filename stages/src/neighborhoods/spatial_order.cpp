#include "slipfit/neighborhoods/spatial_order.h"

namespace slipfit {

namespace {
/// The 21 low bits of \a v spread to every third bit.
std::uint64_t spread(std::uint32_t v) {
  std::uint64_t x = v & 0x1fffffu;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}
}  // namespace

std::uint64_t mortonCode(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  return spread(x) | spread(y) << 1 | spread(z) << 2;
}

}  // namespace slipfit
