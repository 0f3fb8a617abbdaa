#pragma once
/// \file Writing a pipeline's points as an ASPRS LAS 1.4 file (ASPRS LAS 1.4 R15): the input's
/// point records when the input was LAS, with the stage fields as described extra bytes (an Extra
/// Bytes VLR, as PDAL, laspy and CloudCompare read them); from a cloud in memory or row by row.

#include "slipfit/pipeline/ply_scalar.h"
#include "slipfit/pipeline/point_data.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace slipfit::pipeline::las {

/// A numeric field of the rows to write: its name and type, and whether a stage wrote it (label,
/// primitive) or it is the input's own (intensity, classification, colours, ...).
struct LasField {
  std::string name;
  ply::Scalar scalar = ply::Scalar::f64;
  bool stage = false;
};

/// The points to write as LAS, read a chunk of rows at a time (a cloud in memory, or the rows of
/// a tiled run's merged segments.ply): their coordinates in the input's frame and their fields.
class LasRows {
 public:
  virtual ~LasRows() = default;
  virtual std::uint64_t size() const = 0;
  virtual const std::vector<LasField>& fields() const = 0;
  /// Makes rows [first, first + count) the current chunk (count ≤ kLasChunk).
  virtual void load(std::uint64_t first, std::uint64_t count) = 0;
  /// Coordinate \a axis of row \a k of the current chunk, in the input's frame.
  virtual double coordinate(std::uint64_t k, int axis) const = 0;
  /// Field \a field (an index into fields()) of row \a k of the current chunk.
  virtual double value(std::size_t field, std::uint64_t k) const = 0;
};

/// The most rows a chunk of LasRows holds.
constexpr std::uint64_t kLasChunk = 1u << 16;

/// What the output keeps of a LAS input: its record format and grid (format −1 and scale 0: the
/// input was not LAS).
struct LasSource {
  int format = -1;
  std::array<double, 3> scale{}, offset{};
};

/// Writes \a rows as LAS 1.4 at \a path.
/// - Coordinates: on the input's grid when it was LAS (\a source); otherwise on a grid of the
///   finest power-of-ten scale, at least 1e-6, that holds the extent in 31 bits, offset the floor
///   of the smallest coordinate (one more pass over the rows).
/// - Record format: the input's (a waveform format without its packets: 4 → 1, 5 → 3, 9 → 6,
///   10 → 8); for another input 7 when it has red/green/blue, else 6. The record's own fields come
///   from the input's fields of their names (as readLas names them); 8-bit colour is widened × 257;
///   a missing field is 0 (return_number and number_of_returns 1).
/// - Extra bytes: every other input field, then the stage's fields (an input field of the same
///   name becomes input_<name>), each in its own type, described in the Extra Bytes VLR (int32
///   fields with no_data −1).
/// Records are written a chunk at a time and the header last. Throws RunError naming the point
/// when a coordinate falls outside the 32-bit grid, and naming the file when it cannot be written.
void writeLas(LasRows& rows, const LasSource& source, const std::string& path);

/// Writes \a data as LAS 1.4 at \a path (writeLas above): its input fields (data.extra, one value
/// each) and the stage fields \a stage_fields (int32, float or uint8 PointData::fields).
void writeLas(const PointData& data, const std::string& path,
              const std::vector<std::string>& stage_fields);

}  // namespace slipfit::pipeline::las
