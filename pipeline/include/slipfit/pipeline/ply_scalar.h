#pragma once
/// \file The scalar types of PLY files (and PCD's 8-byte integers, which a PLY row of a streamed
/// PCD carries): one table of names, sizes and PCL datatypes, and the conversions of one value to
/// and from bytes and text. Every reader and writer of rows uses it: cloud_io (PCL blobs),
/// cloud_stream (rows read by ranges), header_guard (header checks) and the tiling's rows.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace slipfit::pipeline::ply {

/// A numeric type, decided once per property rather than per value.
enum class Scalar : std::uint8_t { i8, u8, i16, u16, i32, u32, i64, u64, f32, f64 };

/// The scalar of a PLY property type name, in either spelling (char or int8, float or float32,
/// ...); nullopt for anything else. With \a wide, int64 and uint64 too (not PLY types, but the
/// rows streamed from a PCD carry them).
std::optional<Scalar> scalarNamed(const std::string& name, bool wide = false);
/// The short PLY name (char, uchar, short, ushort, int, uint, float, double; int64, uint64).
const char* scalarName(Scalar scalar);
/// Bytes of one value.
std::size_t scalarBytes(Scalar scalar);
bool isFloating(Scalar scalar);
bool isSigned(Scalar scalar);

/// The scalar of a pcl::PCLPointField datatype (INT8 ... FLOAT64); nullopt for one PCL 1.13 does
/// not know.
std::optional<Scalar> scalarOfDatatype(std::uint8_t datatype);
/// The pcl::PCLPointField datatype of \a scalar; nullopt for the wide integers.
std::optional<std::uint8_t> datatypeOfScalar(Scalar scalar);
/// Bytes of one value of a PCLPointField datatype; 0 for one PCL 1.13 does not know.
std::size_t datatypeBytes(std::uint8_t datatype);

/// The little-endian value at \a p as double (64-bit integers rounded to the nearest double).
double decode(Scalar scalar, const void* p);
/// Writes \a value at \a p as \a scalar, little-endian (an integer rounded toward zero).
void encode(Scalar scalar, double value, void* p);
/// Writes the shortest text that reads back to the value at \a p into [out, end); returns the end
/// of what was written.
char* print(Scalar scalar, const void* p, char* out, char* end);
/// Parses \a text as one value of \a scalar and writes it at \a out; false when the text is not a
/// number of that type (trailing characters, out of range, a sign on an unsigned type).
bool parse(Scalar scalar, const std::string& text, void* out);

}  // namespace slipfit::pipeline::ply
