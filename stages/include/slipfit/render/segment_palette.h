#pragma once
/// \file The colour of segment k in segments.ply and the picture: the twelve colours of the
/// Tableau-20 set first, then hues stepped by the golden angle over three saturation / value
/// levels, so that no two of the first 256 segments share a colour and none is the grey of
/// unassigned points.

#include <array>
#include <cstddef>
#include <cstdint>

namespace slipfit {

using Rgb = std::array<std::uint8_t, 3>;

/// The grey of points in no segment.
constexpr Rgb kUnassignedColour{170, 170, 170};

/// The colour of segment \a k (0-based), deterministic.
Rgb segmentColour(std::size_t k);

}  // namespace slipfit
