#include "las_reader.h"

#include "slipfit/pipeline/errors.h"
#include "slipfit/pipeline/ply_scalar.h"

#include <pcl/PCLPointField.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <vector>

namespace slipfit::pipeline::las {

namespace {

using Field = pcl::PCLPointField;

template <typename T>
T at(const std::uint8_t* bytes, std::size_t offset) {
  T v;
  std::memcpy(&v, bytes + offset,
              sizeof v);  // LAS is little-endian, as the hosts slipfit builds on
  return v;
}

/// The bytes of each point data record format's own fields (ASPRS LAS 1.4 R15, tables 7–17).
constexpr std::array<std::uint16_t, 11> kRecordBytes = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};

bool hasGpsTime(int format) {
  return format != 0 && format != 2;
}
bool hasRgb(int format) {
  return format == 2 || format == 3 || format == 5 || format == 7 || format == 8 || format == 10;
}
bool hasNir(int format) {
  return format == 8 || format == 10;
}

/// Where the gps time and the colour sit in a record of \a format.
std::size_t gpsOffset(int format) {
  return format >= 6 ? 22 : 20;
}
std::size_t rgbOffset(int format) {
  if (format >= 6)
    return 30;
  return format == 2 ? 20 : 28;
}

class BlobWriter {
 public:
  explicit BlobWriter(pcl::PCLPointCloud2& blob) : blob_(blob) {}
  void field(const char* name, std::uint8_t datatype, std::uint32_t bytes) {
    Field f;
    f.name = name;
    f.offset = blob_.point_step;
    f.datatype = datatype;
    f.count = 1;
    blob_.fields.push_back(f);
    blob_.point_step += bytes;
  }

 private:
  pcl::PCLPointCloud2& blob_;
};

/// The PCL datatype an extra bytes field is read as: its own, double for 64-bit integers (PLY and
/// the tiles have no such type) and for scaled values.
std::uint8_t extraDatatype(const ExtraBytesField& e) {
  const ply::Scalar scalar = extraScalar(e.data_type);
  if (e.scaled || scalar == ply::Scalar::i64 || scalar == ply::Scalar::u64)
    return Field::FLOAT64;
  return *ply::datatypeOfScalar(scalar);
}

/// The fields of the Extra Bytes VLR among the VLRs between the header and the points.
std::vector<ExtraBytesField> readExtraBytes(std::ifstream& in, std::uint64_t header_size,
                                            std::uint32_t vlrs, std::uint64_t data_offset,
                                            int format, std::uint16_t record_bytes,
                                            const std::string& where) {
  std::vector<ExtraBytesField> fields;
  std::uint64_t at_byte = header_size;
  for (std::uint32_t v = 0; v < vlrs && at_byte + 54 <= data_offset; ++v) {
    std::array<std::uint8_t, 54> h{};
    in.clear();
    in.seekg(static_cast<std::streamoff>(at_byte));
    if (!in.read(reinterpret_cast<char*>(h.data()), h.size()))
      throw RunError(where + "truncated variable length record " + std::to_string(v));
    const auto length = at<std::uint16_t>(h.data(), 20);
    const bool extra =
        std::memcmp(h.data() + 2, "LASF_Spec\0", 10) == 0 && at<std::uint16_t>(h.data(), 18) == 4;
    if (extra && at_byte + 54 + length <= data_offset) {
      std::vector<std::uint8_t> d(length);
      if (!in.read(reinterpret_cast<char*>(d.data()), length))
        throw RunError(where + "truncated Extra Bytes record");
      std::uint32_t offset = formatBytes(format);
      for (std::size_t k = 0; k + 192 <= d.size(); k += 192) {
        const std::uint8_t* e = d.data() + k;
        const int type = e[2];
        const int options = e[3];
        if (type == 0 || type > 10) {  // undocumented bytes (options = their count) or arrays
          offset += type == 0 ? static_cast<std::uint32_t>(options) : record_bytes;
          continue;
        }
        ExtraBytesField f;
        f.data_type = type;
        f.offset = static_cast<std::uint16_t>(std::min<std::uint32_t>(offset, 0xFFFF));
        const char* name = reinterpret_cast<const char*>(e + 4);
        f.name.assign(name, strnlen(name, 32));
        for (char& c : f.name)
          if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_'))
            c = '_';
        if (f.name.empty() || std::isdigit(static_cast<unsigned char>(f.name[0])))
          f.name = "extra_" + f.name;
        if (options & 8)
          f.scale = at<double>(e, 112);
        if (options & 16)
          f.offset_value = at<double>(e, 136);
        f.scaled = (options & 24) != 0;
        offset += static_cast<std::uint32_t>(ply::scalarBytes(extraScalar(type)));
        if (offset > record_bytes)
          throw RunError(where + "extra bytes field '" + f.name + "' ends at byte " +
                         std::to_string(offset) + " of records of " + std::to_string(record_bytes) +
                         " bytes");
        if (f.scaled && !(std::isfinite(f.scale) && std::isfinite(f.offset_value)))
          throw RunError(where + "extra bytes field '" + f.name +
                         "' has a scale or offset that is not finite");
        fields.push_back(std::move(f));
      }
    }
    at_byte += 54 + std::uint64_t{length};
  }
  return fields;
}

}  // namespace

ply::Scalar extraScalar(int data_type) {
  static constexpr ply::Scalar kScalars[] = {
      ply::Scalar::u8,  ply::Scalar::i8,  ply::Scalar::u16, ply::Scalar::i16, ply::Scalar::u32,
      ply::Scalar::i32, ply::Scalar::u64, ply::Scalar::i64, ply::Scalar::f32, ply::Scalar::f64};
  return kScalars[data_type - 1];
}

std::uint16_t formatBytes(int format) {
  return kRecordBytes[static_cast<std::size_t>(format)];
}

LasHeader readLasHeader(const std::string& path, const std::string& where) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw RunError(where + "cannot be opened");
  std::error_code ec;
  const std::uint64_t file_size = std::filesystem::file_size(path, ec);
  if (ec)
    throw RunError(where + "cannot be opened (" + ec.message() + ")");
  constexpr std::size_t kSmallestHeader = 227;  // LAS 1.0–1.2
  std::array<std::uint8_t, 375> h{};
  const std::size_t head = static_cast<std::size_t>(std::min<std::uint64_t>(file_size, h.size()));
  in.read(reinterpret_cast<char*>(h.data()), static_cast<std::streamsize>(head));
  if (head < 4 || std::memcmp(h.data(), "LASF", 4) != 0)
    throw RunError(where + "not a LAS file (it does not start with \"LASF\")");
  if (head < kSmallestHeader)
    throw RunError(where + "truncated LAS header (" + std::to_string(head) + " bytes, at least " +
                   std::to_string(kSmallestHeader) + " expected)");
  const int major = h[24], minor = h[25];
  if (major != 1 || minor > 4)
    throw RunError(where + "LAS version " + std::to_string(major) + "." + std::to_string(minor) +
                   " (versions 1.0 to 1.4 are read)");
  const auto header_size = at<std::uint16_t>(h.data(), 94);
  const auto data_offset = at<std::uint32_t>(h.data(), 96);
  const int format_byte = h[104];
  const auto record_bytes = at<std::uint16_t>(h.data(), 105);
  if (format_byte & 0xC0)
    throw RunError(where + "compressed LAS (LAZ, record format byte " +
                   std::to_string(format_byte) +
                   "): decompress it first, e.g. `pdal translate in.laz out.las` or "
                   "`laszip -i in.laz -o out.las`");
  const int format = format_byte;
  if (format > 10)
    throw RunError(where + "point data record format " + std::to_string(format) +
                   " (formats 0 to 10 are defined)");
  const std::size_t needed_header = minor >= 4 ? 375 : minor == 3 ? 235 : kSmallestHeader;
  if (header_size < needed_header || header_size > file_size)
    throw RunError(where + "header size " + std::to_string(header_size) + " (LAS 1." +
                   std::to_string(minor) + " needs " + std::to_string(needed_header) +
                   ", the file has " + std::to_string(file_size) + " bytes)");
  if (head < needed_header)
    throw RunError(where + "truncated LAS header");
  if (record_bytes < kRecordBytes[static_cast<std::size_t>(format)])
    throw RunError(where + "point records of " + std::to_string(record_bytes) +
                   " bytes, under the " +
                   std::to_string(kRecordBytes[static_cast<std::size_t>(format)]) +
                   " of record format " + std::to_string(format));
  std::uint64_t count = at<std::uint32_t>(h.data(), 107);
  if (minor >= 4) {
    const auto wide = at<std::uint64_t>(h.data(), 247);
    if (count != 0 && wide != 0 && wide != count)
      throw RunError(where + "the header gives two point counts (" + std::to_string(count) +
                     " and " + std::to_string(wide) + ")");
    count = wide != 0 ? wide : count;
  }
  if (data_offset < header_size || data_offset > file_size)
    throw RunError(where + "point data offset " + std::to_string(data_offset) +
                   " outside the file (header " + std::to_string(header_size) + ", file " +
                   std::to_string(file_size) + " bytes)");
  if (count == 0)
    throw RunError(where + "the cloud is empty (0 points)");
  if (count > (file_size - data_offset) / record_bytes)
    throw RunError(where + "truncated: the header announces " + std::to_string(count) +
                   " points of " + std::to_string(record_bytes) + " bytes but the file holds " +
                   std::to_string((file_size - data_offset) / record_bytes));
  LasHeader header;
  header.minor = minor;
  header.format = format;
  header.record_bytes = record_bytes;
  header.data_offset = data_offset;
  header.count = count;
  for (int a = 0; a < 3; ++a) {
    const auto i = static_cast<std::size_t>(a);
    header.scale[i] = at<double>(h.data(), 131 + 8 * i);
    header.offset[i] = at<double>(h.data(), 155 + 8 * i);
    if (!(std::isfinite(header.scale[i]) && header.scale[i] != 0.0 &&
          std::isfinite(header.offset[i])))
      throw RunError(where + "scale or offset of " + "xyz"[a] + " is zero or not finite");
  }
  header.extra = readExtraBytes(in, header_size, at<std::uint32_t>(h.data(), 100), data_offset,
                                format, record_bytes, where);
  return header;
}

std::vector<Field> decodedFields(const LasHeader& header, std::uint32_t& row_bytes) {
  const int format = header.format;
  pcl::PCLPointCloud2 blob;
  BlobWriter fields(blob);
  fields.field("x", Field::FLOAT64, 8);
  fields.field("y", Field::FLOAT64, 8);
  fields.field("z", Field::FLOAT64, 8);
  fields.field("intensity", Field::UINT16, 2);
  fields.field("return_number", Field::UINT8, 1);
  fields.field("number_of_returns", Field::UINT8, 1);
  fields.field("classification", Field::UINT8, 1);
  fields.field("classification_flags", Field::UINT8, 1);
  fields.field("scan_direction_flag", Field::UINT8, 1);
  fields.field("edge_of_flight_line", Field::UINT8, 1);
  fields.field("user_data", Field::UINT8, 1);
  if (format >= 6) {
    fields.field("scanner_channel", Field::UINT8, 1);
    fields.field("scan_angle", Field::INT16, 2);
  } else {
    fields.field("scan_angle_rank", Field::INT8, 1);
  }
  fields.field("point_source_id", Field::UINT16, 2);
  if (hasGpsTime(format))
    fields.field("gps_time", Field::FLOAT64, 8);
  if (hasRgb(format)) {
    fields.field("red", Field::UINT16, 2);
    fields.field("green", Field::UINT16, 2);
    fields.field("blue", Field::UINT16, 2);
  }
  if (hasNir(format))
    fields.field("nir", Field::UINT16, 2);
  std::vector<std::string> names;
  for (const Field& f : blob.fields)
    names.push_back(f.name);
  for (const ExtraBytesField& e : header.extra) {
    std::string name = e.name;
    while (std::find(names.begin(), names.end(), name) != names.end())
      name = "extra_" + name;
    names.push_back(name);
    const std::uint8_t datatype = extraDatatype(e);
    fields.field(name.c_str(), datatype, static_cast<std::uint32_t>(ply::datatypeBytes(datatype)));
  }
  row_bytes = blob.point_step;
  return blob.fields;
}

void decodeRecord(const LasHeader& header, const std::uint8_t* r, std::uint8_t* o) {
  const int format = header.format;
  std::size_t w = 0;
  const auto put = [&](auto value) {
    std::memcpy(o + w, &value, sizeof value);
    w += sizeof value;
  };
  for (std::size_t a = 0; a < 3; ++a)
    put(header.offset[a] + header.scale[a] * at<std::int32_t>(r, 4 * a));
  put(at<std::uint16_t>(r, 12));
  const std::uint8_t returns = r[14];
  if (format >= 6) {
    const std::uint8_t flags = r[15];
    put(static_cast<std::uint8_t>(returns & 0x0F));
    put(static_cast<std::uint8_t>(returns >> 4));
    put(r[16]);                                        // classification
    put(static_cast<std::uint8_t>(flags & 0x0F));      // synthetic, key point, withheld, overlap
    put(static_cast<std::uint8_t>((flags >> 6) & 1));  // scan direction
    put(static_cast<std::uint8_t>(flags >> 7));        // edge of flight line
    put(r[17]);                                        // user data
    put(static_cast<std::uint8_t>((flags >> 4) & 3));  // scanner channel
    put(at<std::int16_t>(r, 18));                      // scan angle, 0.006°
    put(at<std::uint16_t>(r, 20));                     // point source id
  } else {
    const std::uint8_t classification = r[15];
    put(static_cast<std::uint8_t>(returns & 0x07));
    put(static_cast<std::uint8_t>((returns >> 3) & 0x07));
    put(static_cast<std::uint8_t>(classification & 0x1F));
    put(static_cast<std::uint8_t>(classification >> 5));
    put(static_cast<std::uint8_t>((returns >> 6) & 1));
    put(static_cast<std::uint8_t>(returns >> 7));
    put(r[17]);                     // user data
    put(at<std::int8_t>(r, 16));    // scan angle rank, degrees
    put(at<std::uint16_t>(r, 18));  // point source id
  }
  if (hasGpsTime(format))
    put(at<double>(r, gpsOffset(format)));
  if (hasRgb(format))
    for (std::size_t c = 0; c < 3; ++c)
      put(at<std::uint16_t>(r, rgbOffset(format) + 2 * c));
  if (hasNir(format))
    put(at<std::uint16_t>(r, 36));
  for (const ExtraBytesField& e : header.extra) {
    const ply::Scalar scalar = extraScalar(e.data_type);
    if (e.scaled || scalar == ply::Scalar::i64 || scalar == ply::Scalar::u64) {
      put(ply::decode(scalar, r + e.offset) * e.scale + e.offset_value);
    } else {  // stored as it is read
      std::memcpy(o + w, r + e.offset, ply::scalarBytes(scalar));
      w += ply::scalarBytes(scalar);
    }
  }
}

pcl::PCLPointCloud2 readLas(const std::string& path, const std::string& where,
                            LasHeader* header_out) {
  const LasHeader header = readLasHeader(path, where);
  if (header_out)
    *header_out = header;
  const std::uint64_t count = header.count;
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw RunError(where + "cannot be opened");

  pcl::PCLPointCloud2 blob;
  blob.fields = decodedFields(header, blob.point_step);
  blob.height = 1;
  blob.width = static_cast<std::uint32_t>(
      std::min<std::uint64_t>(count, std::numeric_limits<std::uint32_t>::max()));
  if (blob.width != count)
    throw RunError(where + std::to_string(count) + " points: more than one cloud holds (" +
                   std::to_string(blob.width) + "); tile it (tiling.size)");
  blob.is_bigendian = false;
  blob.is_dense = true;
  blob.row_step = blob.point_step * blob.width;
  blob.data.resize(static_cast<std::size_t>(count) * blob.point_step);

  // The records, a chunk at a time, into the blob's rows.
  in.seekg(static_cast<std::streamoff>(header.data_offset));
  constexpr std::uint64_t kChunk = 1 << 16;
  std::vector<std::uint8_t> records;
  for (std::uint64_t first = 0; first < count; first += kChunk) {
    const std::uint64_t n = std::min(kChunk, count - first);
    records.resize(static_cast<std::size_t>(n * header.record_bytes));
    in.read(reinterpret_cast<char*>(records.data()), static_cast<std::streamsize>(records.size()));
    if (!in)
      throw RunError(where + "truncated: reading point " + std::to_string(first) + " failed");
    for (std::uint64_t k = 0; k < n; ++k)
      decodeRecord(header, records.data() + k * header.record_bytes,
                   blob.data.data() + (first + k) * blob.point_step);
  }
  return blob;
}

}  // namespace slipfit::pipeline::las
