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

/// Reads and writes one field of little-endian rows, converting to and from double (an integer
/// field takes a written value rounded toward zero).
struct FieldAt {
  ply::Scalar scalar = ply::Scalar::f64;
  std::uint64_t offset = 0;
  double get(const char* row) const { return ply::decode(scalar, row + offset); }
  void set(char* row, double value) const { ply::encode(scalar, value, row + offset); }
};
inline FieldAt fieldAt(const StreamField& field) {
  return {field.scalar, field.offset};
}

/// Copies the fields of \a to from rows laid out as \a from (by name; each must exist there with
/// the same size), as a few contiguous spans.
class RowCopy {
 public:
  RowCopy(const std::vector<StreamField>& from, const std::vector<StreamField>& to);
  void apply(const char* source, char* target) const;

 private:
  struct Span {
    std::uint64_t from, to, bytes;
  };
  std::vector<Span> spans_;
};

/// Writes \a bytes to \a out; throws RunError naming \a path when the write fails (disk full).
void writeOrFail(std::ofstream& out, const char* bytes, std::size_t size, const std::string& path);

/// An existing file written at given offsets, by several threads at once (pwrite(2)): the rows of
/// each tile go to their own place.
class PositionalFile {
 public:
  /// Opens \a path for writing; throws RunError naming it when it cannot.
  explicit PositionalFile(const std::string& path);
  ~PositionalFile();
  PositionalFile(const PositionalFile&) = delete;
  PositionalFile& operator=(const PositionalFile&) = delete;
  /// Writes \a size bytes at \a offset; throws RunError naming the file when the write fails.
  void write(std::uint64_t offset, const char* bytes, std::size_t size) const;
  /// Closes the file; throws RunError when that reports an error.
  void close();

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace slipfit::pipeline::tiling
