#pragma once
/// \file PNG pictures, written with libpng's simplified API: a failure (a full disk, a write
/// error) is one RunError line, as for every other output, and leaves no partial file. PCL's
/// saveRgbPNGFile went through VTK, which printed its own coloured lines and deleted the file,
/// so that the run then said its temporary file "has gone".

#include <cstdint>
#include <string>
#include <vector>

namespace slipfit::pipeline::detail {

/// Writes \a rgb (width × height × 3 bytes, rows from the top) to \a path as an 8-bit RGB PNG.
/// Throws RunError naming the file ("write failed (disk full?)" for a write error).
void writeRgbPng(const std::string& path, const std::vector<std::uint8_t>& rgb, int width,
                 int height);

}  // namespace slipfit::pipeline::detail
