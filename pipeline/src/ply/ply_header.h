#pragma once
/// \file The header of a PLY file of one vertex element: read (the elements, their properties
/// and where the data starts, refusing what PCL's reader would crash on) and written as slipfit
/// writes it: segments.ply, cloud.ply, the tiles of a tiled run and its merged output.

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

/// A property as the header declares it.
struct HeaderProperty {
  std::string name;
  Scalar scalar = Scalar::f32;  ///< a list's item type
  bool list = false;
  std::size_t min_bytes = 0;  ///< binary: the scalar, or the count of an empty list
  int line = 0;               ///< the header line, for messages
};

struct HeaderElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<HeaderProperty> properties;
};

/// What a PLY header says.
struct Header {
  std::string format;  ///< ascii, binary_little_endian or binary_big_endian
  std::vector<HeaderElement> elements;
  /// As PCL tracks them: obj_info num_cols / num_rows, else the vertex count and 1.
  std::uint64_t width = 0, height = 0;
  std::size_t end = 0;  ///< bytes of the header, "ply" to "end_header\n": the data starts here
  /// The element named \a name, or nullptr.
  const HeaderElement* element(const std::string& name) const;
};

/// Parses the header at the start of \a head (the file's first bytes, detail::readHead) of a file
/// of \a file_size bytes, line by line as PCL's PLYReader reads it. Throws RunError prefixed by
/// \a where and naming the line ("PLY header line 7: ...") for a malformed or unsupported line,
/// a count the file cannot hold, a second format, element or property of one name, a list
/// property in the vertex element, and a header without format or end_header.
Header parseHeader(const std::string& head, std::uint64_t file_size, const std::string& where);

}  // namespace slipfit::pipeline::ply
