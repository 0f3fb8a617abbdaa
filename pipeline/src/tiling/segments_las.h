#pragma once
/// \file segments.las of a tiled run: the merged segments.ply's rows written as LAS, the fields
/// the untiled run's segments.las holds (las_writer.h), a chunk of rows at a time.

#include <string>

namespace slipfit::pipeline::tiling {

/// Writes the merged segments.ply \a ply as LAS at \a path: its coordinates (on the grid and in the
/// record format of \a input when that is a LAS file), the input's fields (those segments.ply
/// keeps as input_<name> because the segmentation writes <name> too under their own names again)
/// and the segmentation's label and primitive as extra bytes; not the normals nor the segment
/// colours, as the untiled run. Throws RunError naming the file that cannot be read or written.
void writeSegmentsLas(const std::string& ply, const std::string& input, const std::string& path);

}  // namespace slipfit::pipeline::tiling
