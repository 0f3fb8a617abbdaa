#pragma once
/// \file Checks of a PLY or PCD header before PCL's readers see the file. PCL 1.13's readers trust
/// their headers: they allocate what a header announces (one "element vertex -4" became an 86 GB
/// allocation), abort on layouts they do not expect (Debian builds PCL with assertions: a list
/// property in the vertex element, an alpha without colours, an obj_info line indented by a
/// space), and write past their buffers when a PCD's SIZE and TYPE disagree. Every such header is
/// refused here with a RunError that names the file and the line. All found by tests/fuzz.

#include <pcl/PCLPointCloud2.h>

#include <cstdint>
#include <string>

namespace slipfit::pipeline::detail {

/// Refuses a PLY header that PCL's PLYReader would crash on or turn into an allocation or a loop
/// the file cannot back: malformed element, property or obj_info lines, counts that are not
/// numbers or exceed what the file size allows, list properties or malformed colours in the
/// vertex element, and grids (obj_info num_cols × num_rows) that match no element.
/// \a where prefixes the message ("input 'f.ply': ").
void checkPlyHeader(const std::string& path, const std::string& where);

/// Refuses a PCD header whose counts are not numbers or announce more data than the file can hold,
/// and whose SIZE, TYPE or COUNT values PCL would turn into a broken record layout; then checks
/// its data against it (data_guard.h).
void checkPcdHeaderText(const std::string& path, const std::string& where);

/// After PCL's PCDReader::readHeader, before PCDReader::read: every field must have a known type
/// and the fields must tile the record exactly (PCL writes each value with the size of its TYPE),
/// and the buffer PCL sized at the POINTS line must hold every record.
void checkPcdLayout(const pcl::PCLPointCloud2& header, const std::string& where);

}  // namespace slipfit::pipeline::detail
