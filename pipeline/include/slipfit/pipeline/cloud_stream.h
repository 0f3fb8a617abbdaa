#pragma once
/// \file The rows of a PLY or PCD file read by ranges, without loading the file: binary files (PLY
/// little or big endian, PCD binary) by one seek per range, ascii files by reading on (a range
/// before the rows already read starts the reading again from the first row: read in increasing
/// order, each row is parsed once a pass). The tiler of a tiled run streams its input through it
/// (docs/TILING.md). A PLY header is read by the parser the header guard uses (ply_header.h), not
/// by PCL's PLYReader::readHeader, which reads the whole file.

#include "slipfit/pipeline/ply_scalar.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace slipfit::pipeline {

namespace las {
struct LasHeader;
}

/// One scalar property of a streamed row: its type (a PCD field of 8-byte integers is int64 or
/// uint64) and its place in the little-endian row that readRecords returns. A PCD field of COUNT
/// k becomes k fields NAME_0 ...
struct StreamField {
  std::string name;
  ply::Scalar scalar = ply::Scalar::f32;
  std::uint32_t bytes = 0;  ///< ply::scalarBytes(scalar)
  std::uint64_t offset = 0;
};

class CloudStream {
 public:
  /// Opens \a path (a PLY, a PCD, or a LAS file: told by its first bytes) and reads its header.
  /// Throws RunError naming the file and the header line for what it cannot stream: no x, y, z, a
  /// list property in the vertex element or before it, compressed PCD or LAS, a binary file
  /// shorter than its header announces.
  explicit CloudStream(const std::string& path);

  /// Points in the file.
  std::uint64_t size() const { return points_; }
  /// The file stores x, y, z as double.
  bool doubleCoordinates() const { return coordinate_bytes_ == 8; }
  /// The sensor of a PCD that is a sensor's view, as readCloud tells it (organized, or a VIEWPOINT
  /// other than the identity at the origin): its origin in the file's coordinates and its
  /// orientation (w, x, y, z); empty for other files.
  const std::optional<std::array<double, 7>>& sensor() const { return sensor_; }
  /// Every property of a row, in the file's order.
  const std::vector<StreamField>& fields() const { return fields_; }
  /// Bytes of one row as readRecords returns it (the sum of the fields' bytes).
  std::uint64_t recordBytes() const { return record_bytes_; }

  /// Reads rows [first, first + count) whole, as count × recordBytes() bytes in little-endian
  /// order (binary files as stored, big-endian ones swapped; ascii text converted to each
  /// field's type). The same errors as read().
  void readRecords(std::uint64_t first, std::uint64_t count, std::vector<char>& rows);

  /// Reads points [first, first + count) as 3 × count doubles (as stored: a float widens
  /// exactly). Throws RunError when the range passes the end, when the file ends early or a value
  /// does not parse.
  void read(std::uint64_t first, std::uint64_t count, Eigen::Matrix3Xd& xyz);

 private:
  enum class Encoding { ascii, little_endian, big_endian, las };
  /// The next header line, without a trailing CR, and its words; false at the end of the file.
  bool headerLine(std::string& line, std::vector<std::string>& words, int& number);
  void parsePly();
  void parsePcd();
  void parseLas();
  void readLasRecords(std::uint64_t first, std::uint64_t count, std::vector<char>& rows);
  [[noreturn]] void fail(const std::string& what) const;
  void addField(const std::string& name, ply::Scalar scalar);
  void checkRange(std::uint64_t first, std::uint64_t count) const;
  void readAsciiRecords(std::uint64_t first, std::uint64_t count, std::vector<char>& rows);

  std::string path_;
  std::ifstream in_;
  Encoding encoding_ = Encoding::ascii;
  std::uint64_t points_ = 0;
  std::uint64_t data_offset_ = 0;        ///< byte where the points' rows start
  std::uint64_t record_bytes_ = 0;       ///< binary: bytes per row
  std::uint64_t offset_[3] = {0, 0, 0};  ///< binary: byte of x, y, z in a row
  int column_[3] = {-1, -1, -1};         ///< token (= field) of x, y, z in a row
  std::vector<StreamField> fields_;
  int coordinate_bytes_ = 4;              ///< 4 (float) or 8 (double), the same for x, y and z
  int columns_ = 0;                       ///< ascii: tokens per row
  std::uint64_t next_row_ = 0;            ///< ascii: the row the stream stands at
  std::uint64_t ascii_lines_before_ = 0;  ///< ascii PLY: rows of elements before the vertices
  bool started_ = false;                  ///< ascii: the stream stands in the data
  bool coordinate_bytes_set_ = false;
  std::shared_ptr<const las::LasHeader> las_;  ///< LAS: how its records decode
  std::optional<std::array<double, 7>> sensor_;
};

}  // namespace slipfit::pipeline
