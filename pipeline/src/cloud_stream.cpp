#include "slipfit/pipeline/cloud_stream.h"

#include "slipfit/pipeline/errors.h"

#include "header_text.h"
#include "las/las_reader.h"
#include "ply/ply_header.h"
#include "sensor_view.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <sstream>
#include <vector>

namespace slipfit::pipeline {

namespace {

std::vector<std::string> words(const std::string& line) {
  std::istringstream s(line);
  std::vector<std::string> out;
  for (std::string w; s >> w;)
    out.push_back(w);
  return out;
}

/// The type of a PCD field of TYPE \a type and SIZE \a size (nullopt when PCL has none).
std::optional<ply::Scalar> pcdFieldType(const std::string& type, std::uint64_t size) {
  using ply::Scalar;
  if (type == "F")
    return size == 4   ? std::optional(Scalar::f32)
           : size == 8 ? std::optional(Scalar::f64)
                       : std::nullopt;
  const bool is_signed = type == "I";
  if (!is_signed && type != "U")
    return std::nullopt;
  switch (size) {
    case 1:
      return is_signed ? Scalar::i8 : Scalar::u8;
    case 2:
      return is_signed ? Scalar::i16 : Scalar::u16;
    case 4:
      return is_signed ? Scalar::i32 : Scalar::u32;
    case 8:
      return is_signed ? Scalar::i64 : Scalar::u64;
    default:
      return std::nullopt;
  }
}

/// A plain decimal count (header_guard.h's parser, any size).
bool parseCount(const std::string& text, std::uint64_t& value) {
  return detail::parseCount(text, std::numeric_limits<std::uint64_t>::max(), value);
}

}  // namespace

CloudStream::CloudStream(const std::string& path) : path_(path), in_(path, std::ios::binary) {
  if (!in_)
    throw RunError("cannot open '" + path + "'");
  char magic[4] = {};
  in_.read(magic, 4);
  if (in_.gcount() == 4 && std::memcmp(magic, "LASF", 4) == 0) {
    parseLas();
    return;  // readLasHeader checked the records against the file's size
  }
  in_.clear();
  in_.seekg(0);
  std::string first;
  std::getline(in_, first);
  if (!first.empty() && first.back() == '\r')
    first.pop_back();
  in_.clear();
  in_.seekg(0);
  if (first == "ply")
    parsePly();
  else
    parsePcd();
  for (int a = 0; a < 3; ++a)  // the parsers place each coordinate inside a row
    if (offset_[a] + static_cast<std::uint64_t>(coordinate_bytes_) > record_bytes_)
      fail("coordinate " + std::string(1, "xyz"[a]) + " lies outside its row");
  if (encoding_ == Encoding::ascii)
    return;
  // A binary header must not announce more rows than the file holds.
  in_.seekg(0, std::ios::end);
  const auto bytes = static_cast<std::uint64_t>(in_.tellg());
  if (record_bytes_ == 0 || bytes < data_offset_ ||
      points_ > (bytes - data_offset_) / record_bytes_)
    fail("the header announces " + std::to_string(points_) + " points of " +
         std::to_string(record_bytes_) + " bytes; the file holds " +
         std::to_string(record_bytes_ ? (bytes - std::min(bytes, data_offset_)) / record_bytes_
                                      : 0));
}

void CloudStream::fail(const std::string& what) const {
  throw RunError("'" + path_ + "': " + what);
}

void CloudStream::addField(const std::string& name, ply::Scalar scalar) {
  const auto bytes = static_cast<std::uint32_t>(ply::scalarBytes(scalar));
  fields_.push_back({name, scalar, bytes, record_bytes_});
  record_bytes_ += bytes;
}

bool CloudStream::headerLine(std::string& line, std::vector<std::string>& w, int& number) {
  if (!std::getline(in_, line))
    return false;
  ++number;
  if (!line.empty() && line.back() == '\r')
    line.pop_back();
  w = words(line);
  return true;
}

void CloudStream::parsePly() {
  // The header is read as PCL's reader reads it (ply_header.h): the same checks as an untiled run.
  std::uint64_t file_size = 0;
  const std::string head = detail::readHead(path_, file_size);
  const ply::Header header = ply::parseHeader(head, file_size, "'" + path_ + "': ");
  encoding_ = header.format == "ascii"                  ? Encoding::ascii
              : header.format == "binary_little_endian" ? Encoding::little_endian
                                                        : Encoding::big_endian;
  // Rows of the elements before the vertices are skipped: as lines (ascii) or bytes (binary).
  std::uint64_t skip_bytes = 0, skip_lines = 0;
  const ply::HeaderElement* vertex = nullptr;
  for (const ply::HeaderElement& e : header.elements) {
    if (e.name == "vertex") {
      vertex = &e;
      break;
    }
    std::uint64_t record = 0;
    for (const ply::HeaderProperty& p : e.properties) {
      if (p.list)
        fail("line " + std::to_string(p.line) +
             ": a list property before the vertex element cannot be read by rows");
      record += p.min_bytes;
    }
    if (record > 0 && e.count > (std::numeric_limits<std::uint64_t>::max() - skip_bytes) / record)
      fail("the elements before the vertices exceed any file");
    skip_bytes += e.count * record;
    skip_lines += e.count;
  }
  if (!vertex)
    fail("no vertex element");
  points_ = vertex->count;
  std::optional<ply::Scalar> coordinate_type;
  int property = 0;
  for (const ply::HeaderProperty& p : vertex->properties) {
    const std::string at = "line " + std::to_string(p.line) + ": ";
    for (int a = 0; a < 3; ++a)
      if (p.name == std::string(1, "xyz"[a])) {
        if (!ply::isFloating(p.scalar))
          fail(at + "coordinate " + p.name + " is not float or double");
        if (coordinate_type && ply::scalarBytes(*coordinate_type) != ply::scalarBytes(p.scalar))
          fail(at + "x, y and z must have one type");
        coordinate_type = p.scalar;
        offset_[a] = record_bytes_;
        column_[a] = property;
      }
    addField(p.name, p.scalar);
    ++property;
  }
  if (column_[0] < 0 || column_[1] < 0 || column_[2] < 0)
    fail("the vertex element has no x, y and z");
  coordinate_bytes_ = static_cast<int>(ply::scalarBytes(*coordinate_type));
  columns_ = property;
  data_offset_ = header.end;
  if (encoding_ == Encoding::ascii)
    ascii_lines_before_ = skip_lines;
  else
    data_offset_ += skip_bytes;
}

void CloudStream::parsePcd() {
  std::string line;
  int number = 0;
  std::vector<std::string> fields, sizes, types, counts;
  std::uint64_t width = 0, height = 1;
  bool has_points = false;
  // PCL's default VIEWPOINT: the identity at the origin.
  std::array<double, 7> viewpoint = {0, 0, 0, 1, 0, 0, 0};
  std::vector<std::string> w;
  while (headerLine(line, w, number)) {
    const std::string at = "line " + std::to_string(number) + ": ";
    if (w.empty() || w[0][0] == '#')
      continue;
    const std::vector<std::string> rest(w.begin() + 1, w.end());
    if (w[0] == "VIEWPOINT") {
      // As PCL reads it; a line it cannot read leaves the default, as PCL's reader does.
      std::array<double, 7> v{};
      bool read = rest.size() == 7;
      for (std::size_t k = 0; read && k < 7; ++k) {
        char* end = nullptr;
        v[k] = std::strtod(rest[k].c_str(), &end);
        read = end && *end == '\0' && std::isfinite(v[k]);
      }
      if (read)
        viewpoint = v;
      continue;
    }
    if (w[0] == "VERSION")
      continue;
    if (w[0] == "FIELDS" || w[0] == "COLUMNS")
      fields = rest;
    else if (w[0] == "SIZE")
      sizes = rest;
    else if (w[0] == "TYPE")
      types = rest;
    else if (w[0] == "COUNT")
      counts = rest;
    else if (w[0] == "WIDTH" && (rest.size() != 1 || !parseCount(rest[0], width)))
      fail(at + "WIDTH is not a count");
    else if (w[0] == "HEIGHT" && (rest.size() != 1 || !parseCount(rest[0], height)))
      fail(at + "HEIGHT is not a count");
    else if (w[0] == "POINTS") {
      if (rest.size() != 1 || !parseCount(rest[0], points_))
        fail(at + "POINTS is not a count");
      has_points = true;
    } else if (w[0] == "DATA") {
      if (rest.size() != 1 || (rest[0] != "ascii" && rest[0] != "binary"))
        fail(at + "DATA " + (rest.empty() ? "" : rest[0]) +
             " cannot be read by rows (ascii and binary can; binary_compressed cannot)");
      encoding_ = rest[0] == "ascii" ? Encoding::ascii : Encoding::little_endian;
      if (counts.empty())
        counts.assign(fields.size(), "1");
      if (sizes.size() != fields.size() || types.size() != fields.size() ||
          counts.size() != fields.size())
        fail(at + "FIELDS, SIZE, TYPE and COUNT differ in length");
      int column = 0;
      for (std::size_t f = 0; f < fields.size(); ++f) {
        std::uint64_t size = 0, count = 0;
        constexpr std::uint64_t kMostValues = 1u << 20;  // per field; PCL's largest is 308
        if (!parseCount(sizes[f], size) || !parseCount(counts[f], count) ||
            (size != 1 && size != 2 && size != 4 && size != 8) || count == 0 || count > kMostValues)
          fail(at + "field " + fields[f] + " has a bad SIZE or COUNT");
        for (int a = 0; a < 3; ++a)
          if (fields[f] == std::string(1, "xyz"[a])) {
            if (types[f] != "F" || count != 1 || (size != 4 && size != 8))
              fail("coordinate " + fields[f] + " is not one float or double");
            if (coordinate_bytes_set_ && static_cast<int>(size) != coordinate_bytes_)
              fail("x, y and z must have one type");
            coordinate_bytes_ = static_cast<int>(size);
            coordinate_bytes_set_ = true;
            offset_[a] = record_bytes_;
            column_[a] = column;
          }
        const std::optional<ply::Scalar> type = pcdFieldType(types[f], size);
        if (!type)
          fail(at + "field " + fields[f] + " has TYPE " + types[f] + " of SIZE " + sizes[f]);
        for (std::uint64_t k = 0; k < count; ++k)
          addField(count == 1 ? fields[f] : fields[f] + "_" + std::to_string(k), *type);
        column += static_cast<int>(count);
      }
      if (column_[0] < 0 || column_[1] < 0 || column_[2] < 0)
        fail("the fields have no x, y and z");
      columns_ = column;
      if (!has_points)
        points_ = width * height;
      data_offset_ = static_cast<std::uint64_t>(in_.tellg());
      if (isSensorView(Eigen::Vector3d(viewpoint[0], viewpoint[1], viewpoint[2]),
                       Eigen::Quaterniond(viewpoint[3], viewpoint[4], viewpoint[5], viewpoint[6]),
                       height))
        sensor_ = viewpoint;
      return;
    } else if (w[0] != "WIDTH" && w[0] != "HEIGHT") {
      fail(at + "not a PLY or PCD header line: '" + line + "'");
    }
  }
  fail("the header has no DATA line");
}

void CloudStream::parseLas() {
  auto header =
      std::make_shared<const las::LasHeader>(las::readLasHeader(path_, "'" + path_ + "': "));
  encoding_ = Encoding::las;
  points_ = header->count;
  data_offset_ = header->data_offset;
  std::uint32_t row_bytes = 0;
  for (const pcl::PCLPointField& f : las::decodedFields(*header, row_bytes))
    addField(f.name, *ply::scalarOfDatatype(f.datatype));
  coordinate_bytes_ = 8;
  for (int a = 0; a < 3; ++a) {
    offset_[a] = fields_[static_cast<std::size_t>(a)].offset;
    column_[a] = a;
  }
  las_ = std::move(header);
}

void CloudStream::readLasRecords(std::uint64_t first, std::uint64_t count,
                                 std::vector<char>& rows) {
  const std::uint64_t stored = las_->record_bytes;
  std::vector<std::uint8_t> records(static_cast<std::size_t>(count * stored));
  in_.clear();
  in_.seekg(static_cast<std::streamoff>(data_offset_ + first * stored));
  if (!in_.read(reinterpret_cast<char*>(records.data()),
                static_cast<std::streamsize>(records.size())))
    fail("the file ends before row " + std::to_string(first + count));
  for (std::uint64_t r = 0; r < count; ++r)
    las::decodeRecord(*las_, records.data() + r * stored,
                      reinterpret_cast<std::uint8_t*>(rows.data() + r * record_bytes_));
}

void CloudStream::checkRange(std::uint64_t first, std::uint64_t count) const {
  if (first > points_ || count > points_ - first)
    fail("rows " + std::to_string(first) + " to " + std::to_string(first + count) +
         " pass the end (" + std::to_string(points_) + " points)");
}

void CloudStream::read(std::uint64_t first, std::uint64_t count, Eigen::Matrix3Xd& xyz) {
  checkRange(first, count);
  xyz.resize(3, static_cast<Eigen::Index>(count));
  constexpr std::uint64_t kRowsPerChunk = 1u << 16;
  std::vector<char> rows;
  for (std::uint64_t done = 0; done < count;) {
    const std::uint64_t n = std::min(kRowsPerChunk, count - done);
    readRecords(first + done, n, rows);
    for (std::uint64_t r = 0; r < n; ++r)
      for (int a = 0; a < 3; ++a) {
        const char* value = rows.data() + r * record_bytes_ + offset_[a];
        double v;
        if (coordinate_bytes_ == 8) {
          std::memcpy(&v, value, 8);
        } else {
          float f;
          std::memcpy(&f, value, 4);
          v = static_cast<double>(f);
        }
        xyz(a, static_cast<Eigen::Index>(done + r)) = v;
      }
    done += n;
  }
}

void CloudStream::readRecords(std::uint64_t first, std::uint64_t count, std::vector<char>& rows) {
  checkRange(first, count);
  rows.resize(count * record_bytes_);
  if (encoding_ == Encoding::ascii) {
    readAsciiRecords(first, count, rows);
    return;
  }
  if (encoding_ == Encoding::las) {
    readLasRecords(first, count, rows);
    return;
  }
  in_.clear();
  in_.seekg(static_cast<std::streamoff>(data_offset_ + first * record_bytes_));
  if (!in_.read(rows.data(), static_cast<std::streamsize>(rows.size())))
    fail("the file ends before row " + std::to_string(first + count));
  if (encoding_ == Encoding::big_endian)
    for (std::uint64_t r = 0; r < count; ++r)
      for (const StreamField& f : fields_) {
        char* value = rows.data() + r * record_bytes_ + f.offset;
        std::reverse(value, value + f.bytes);
      }
}

void CloudStream::readAsciiRecords(std::uint64_t first, std::uint64_t count,
                                   std::vector<char>& rows) {
  if (first < next_row_) {  // a row behind: read again from the first (ascii has no seek)
    in_.clear();
    started_ = false;
    next_row_ = 0;
  }
  std::string line;
  if (!started_) {
    in_.seekg(static_cast<std::streamoff>(data_offset_));
    for (std::uint64_t k = 0; k < ascii_lines_before_; ++k)
      std::getline(in_, line);
    started_ = true;
  }
  for (; next_row_ < first; ++next_row_)
    if (!std::getline(in_, line))
      fail("the file ends before row " + std::to_string(first));
  for (std::uint64_t r = 0; r < count; ++r, ++next_row_) {
    if (!std::getline(in_, line))
      fail("the file ends before row " + std::to_string(first + count));
    const std::vector<std::string> w = words(line);
    if (w.size() < fields_.size())
      fail("row " + std::to_string(next_row_) + " has " + std::to_string(w.size()) +
           " values, the header announces " + std::to_string(columns_));
    for (std::size_t f = 0; f < fields_.size(); ++f)
      if (!ply::parse(fields_[f].scalar, w[f], rows.data() + r * record_bytes_ + fields_[f].offset))
        fail("row " + std::to_string(next_row_) + ": '" + w[f] + "' is not a " +
             ply::scalarName(fields_[f].scalar) + " (" + fields_[f].name + ")");
  }
}

}  // namespace slipfit::pipeline
