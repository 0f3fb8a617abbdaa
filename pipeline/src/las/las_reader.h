#pragma once
/// \file Reading ASPRS LAS 1.0–1.4 point clouds (point data record formats 0–10, uncompressed)
/// into a PCLPointCloud2, as the PLY and PCD readers give theirs: written against the ASPRS LAS
/// 1.4 specification (R15), every size in the header checked against the format and the file
/// before anything is allocated.

#include "slipfit/pipeline/ply_scalar.h"

#include <pcl/PCLPointCloud2.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace slipfit::pipeline::las {

/// One field of a record's extra bytes, as an Extra Bytes VLR (LASF_Spec, record 4) describes it.
struct ExtraBytesField {
  std::string name;
  int data_type = 0;         ///< 1–10: uchar, char, ushort, short, ulong, long, ulonglong, ...
  std::uint16_t offset = 0;  ///< byte in the record
  bool scaled = false;       ///< the value is raw × scale + offset (read as double)
  double scale = 1, offset_value = 0;
};

/// What the public header block says of the points.
struct LasHeader {
  int minor = 0;   ///< version 1.minor
  int format = 0;  ///< point data record format, 0–10
  std::uint16_t record_bytes = 0;
  std::uint32_t data_offset = 0;
  std::uint64_t count = 0;
  std::array<double, 3> scale{}, offset{};
  /// The described extra bytes of each record (those of data type 1–10; others are skipped).
  std::vector<ExtraBytesField> extra;
};

/// The scalar of an extra bytes field of LAS data type \a data_type (1–10: unsigned char, char,
/// unsigned short, short, unsigned long, long, unsigned long long, long long, float, double).
ply::Scalar extraScalar(int data_type);

/// The bytes of the own fields of point data record \a format (0–10).
std::uint16_t formatBytes(int format);

/// The fields a record of \a header's format decodes into, as readLas lists them (its extra bytes
/// last), with their offsets in the decoded row; \a row_bytes receives the row's size.
std::vector<pcl::PCLPointField> decodedFields(const LasHeader& header, std::uint32_t& row_bytes);

/// Decodes one point record (\a header.record_bytes bytes at \a record) into a row of the
/// decodedFields layout at \a row: coordinates as scale × integer + offset.
void decodeRecord(const LasHeader& header, const std::uint8_t* record, std::uint8_t* row);

/// The header of the LAS file at \a path, checked as readLas checks it (against the file's size:
/// the records it announces are there), with the Extra Bytes VLR's fields. Throws RunError as
/// readLas.
LasHeader readLasHeader(const std::string& path, const std::string& where);

/// The points of the LAS file at \a path: x, y, z as FLOAT64 (each record's integer times the
/// header's scale plus its offset: the file's own double frame), then intensity (UINT16),
/// return_number and number_of_returns (UINT8), classification and classification_flags (UINT8;
/// formats 0–5 keep the synthetic, key-point and withheld bits in the flags' low three bits),
/// scan_direction_flag and edge_of_flight_line (UINT8), scanner_channel (UINT8, formats 6–10),
/// scan_angle_rank (INT8, degrees, formats 0–5) or scan_angle (INT16, 0.006° steps, 6–10),
/// user_data (UINT8), point_source_id (UINT16), gps_time (FLOAT64) where the format has it,
/// red/green/blue (UINT16) and nir (UINT16) where it has them, then the extra bytes an Extra
/// Bytes VLR describes under their names (64-bit integers and scaled values as FLOAT64; a name
/// that is not a C identifier gets '_' for each other character, one taken by a standard field
/// the prefix "extra_"). Waveform packets and undescribed extra bytes are not read. \a header,
/// when given, receives the header. Throws RunError
/// prefixed with \a where: not a LAS file, a version past 1.4, a compressed (LAZ) file, a record
/// format outside 0–10, a record shorter than its format, a header whose sizes disagree with the
/// file, or a scale that is zero or not finite.
pcl::PCLPointCloud2 readLas(const std::string& path, const std::string& where,
                            LasHeader* header = nullptr);

}  // namespace slipfit::pipeline::las
