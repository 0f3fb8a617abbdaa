#pragma once
/// \file The header of a PLY file of one vertex element, as slipfit writes it: segments.ply,
/// cloud.ply, the tiles of a tiled run and its merged output.

#include "slipfit/pipeline/ply_scalar.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace slipfit::pipeline::ply {

/// One scalar property of the vertex element: its name and type.
struct Property {
  std::string name;
  Scalar scalar = Scalar::f32;
};

/// The header text, "ply" to "end_header\n", for \a count vertices of \a properties in
/// \a format ("ascii", "binary_little_endian" or "binary_big_endian"). Normals are written as
/// nx, ny, nz (normal_x → nx: the names MeshLab and CloudCompare know).
std::string headerText(const char* format, std::uint64_t count,
                       const std::vector<Property>& properties);

}  // namespace slipfit::pipeline::ply
