#pragma once
/// \file Binary little-endian PLY files of one vertex element written row by row: the tiles and
/// the merged segments.ply of a tiled run, whose rows are copied from CloudStream::readRecords.

#include "slipfit/pipeline/cloud_stream.h"

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

namespace slipfit::pipeline::tiling {

/// The header of a binary little-endian PLY with \a count vertices of \a fields (normals named
/// nx, ny, nz as writeCloudPly names them).
std::string plyHeader(const std::vector<StreamField>& fields, std::uint64_t count);

/// The fields of \a all without those named in \a drop, repacked one after another.
std::vector<StreamField> withoutFields(const std::vector<StreamField>& all,
                                       const std::vector<std::string>& drop);

/// The field named \a name of \a fields, or nullptr.
const StreamField* findField(const std::vector<StreamField>& fields, const std::string& name);

/// Copies each of \a from's fields that \a to also has from the row at \a source to the row at
/// \a target (by name; each to-field must exist in from).
void copyFields(const std::vector<StreamField>& from, const char* source,
                const std::vector<StreamField>& to, char* target);

/// A value of a little-endian row, converted to double (any numeric PLY type).
double fieldValue(const StreamField& field, const char* row);

/// Writes \a value at \a field of \a row, converted to the field's type (an integer type takes
/// the value rounded toward zero).
void setFieldValue(const StreamField& field, char* row, double value);

/// Writes \a bytes to \a out; throws RunError naming \a path when the write fails (disk full).
void writeOrFail(std::ofstream& out, const char* bytes, std::size_t size, const std::string& path);

}  // namespace slipfit::pipeline::tiling
