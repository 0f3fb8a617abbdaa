#pragma once
/// \file Writing a pipeline's points as an ASPRS LAS 1.4 file (ASPRS LAS 1.4 R15): the input's
/// point records when the input was LAS, with the stage fields a caller names as described extra
/// bytes (an Extra Bytes VLR, as PDAL, laspy and CloudCompare read them).

#include "slipfit/pipeline/point_data.h"

#include <string>
#include <vector>

namespace slipfit::pipeline::las {

/// Writes \a data as LAS 1.4 at \a path.
/// - Coordinates: the input's frame (cloud + frame.shift) on the input's grid (frame.grid_scale,
///   grid_offset) when it was LAS; otherwise on a grid of the finest power-of-ten scale, at least
///   1e-6, that holds the extent in 31 bits, offset the floor of the smallest coordinate.
/// - Record format: the input's (a waveform format without its packets: 4 → 1, 5 → 3, 9 → 6,
///   10 → 8); for another input 7 when it has red/green/blue, else 6. The record's own fields come
///   from the input's fields of their names (as readLas names them); 8-bit colour is widened × 257;
///   a missing field is 0 (return_number and number_of_returns 1).
/// - Extra bytes: every other numeric input field with one value, then \a stage_fields (int32 or
///   float or uint8 PointData::fields; an input field of the same name becomes input_<name>),
///   each in its own type, described in the Extra Bytes VLR (int32 fields with no_data −1).
/// Throws RunError naming the point when a coordinate falls outside the 32-bit grid.
void writeLas(const PointData& data, const std::string& path,
              const std::vector<std::string>& stage_fields);

}  // namespace slipfit::pipeline::las
