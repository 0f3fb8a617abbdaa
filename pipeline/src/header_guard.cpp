#include "header_guard.h"
#include "data_guard.h"
#include "header_text.h"
#include "ply/ply_header.h"

#include "slipfit/pipeline/errors.h"
#include "slipfit/pipeline/ply_scalar.h"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <vector>

namespace slipfit::pipeline::detail {

namespace {

using u64 = std::uint64_t;

u64 saturatingAdd(u64 a, u64 b) {
  return a > std::numeric_limits<u64>::max() - b ? std::numeric_limits<u64>::max() : a + b;
}

u64 saturatingMul(u64 a, u64 b) {
  return b != 0 && a > std::numeric_limits<u64>::max() / b ? std::numeric_limits<u64>::max()
                                                           : a * b;
}

// ---------------------------------------------------------------------------------------- PLY

/// PCL maps uchar red, green, blue (or diffuse_*) to one packed rgb field and writes it when it
/// reads blue; alpha amends that field. Any other arrangement makes it write out of place or
/// assert, so the colours must come as red, green, blue (then alpha) in a row.
void checkVertexColours(const ply::HeaderElement& vertex, const std::string& where) {
  static const char* const kColourNames[] = {"red",           "green",        "blue", "diffuse_red",
                                             "diffuse_green", "diffuse_blue", "alpha"};
  std::vector<std::size_t> at;
  std::string names;
  for (std::size_t i = 0; i < vertex.properties.size(); ++i) {
    const ply::HeaderProperty& p = vertex.properties[i];
    const bool colour = !p.list && p.scalar == ply::Scalar::u8 &&
                        std::any_of(std::begin(kColourNames), std::end(kColourNames),
                                    [&](const char* n) { return p.name == n; });
    if (colour) {
      at.push_back(i);
      names += (names.empty() ? "" : " ") + p.name;
    }
  }
  if (at.empty())
    return;
  const bool in_a_row = at.back() - at.front() + 1 == at.size();
  const bool known = names == "red green blue" || names == "red green blue alpha" ||
                     names == "diffuse_red diffuse_green diffuse_blue" ||
                     names == "diffuse_red diffuse_green diffuse_blue alpha";
  if (!in_a_row || !known)
    throw RunError(where + "vertex colours must be uchar red, green, blue (then alpha) in a row; " +
                   "the header has '" + names + "'");
}

}  // namespace

void checkPlyHeader(const std::string& path, const std::string& where) {
  u64 file_size = 0;
  const std::string head = readHead(path, file_size);
  if (head.size() < 4 || head.compare(0, 3, "ply") != 0)
    throw RunError(where + "not a PLY file (it does not start with 'ply')");
  const ply::Header h = ply::parseHeader(head, file_size, where);
  const std::vector<ply::HeaderElement>& elements = h.elements;
  const ply::HeaderElement* vertex = h.element("vertex");
  if (!vertex)
    throw RunError(where + "the PLY header has no vertex element");
  checkVertexColours(*vertex, where);

  // PCL sizes its buffer by num_cols × num_rows when both are given: that grid must be the vertex
  // element or, for organized clouds, the range_grid element that maps cells to vertices.
  const u64 grid = h.width * h.height;
  if (grid != vertex->count) {
    const ply::HeaderElement* range = h.element("range_grid");
    if (!range || range->count != grid || grid < vertex->count)
      throw RunError(where + "obj_info num_cols × num_rows (" + std::to_string(h.width) + " × " +
                     std::to_string(h.height) + ") matches neither the vertex count (" +
                     std::to_string(vertex->count) + ") nor a range_grid element");
  }

  // Every record takes at least its scalars and list counts (binary) or one character and a
  // separator per value (ascii).
  const bool ascii = h.format == "ascii";
  u64 needed = 0;
  for (const auto& e : elements) {
    u64 record = 0;
    for (const auto& p : e.properties)
      record += ascii ? 2 : p.min_bytes;
    if (ascii)
      record = std::max<u64>(record, 1);  // a line, even for an element without properties
    needed = saturatingAdd(needed, saturatingMul(record, e.count));
  }
  const u64 body = file_size - std::min<u64>(file_size, h.end);
  if (needed > body + (ascii ? 1 : 0))
    throw RunError(where + "truncated: the header announces " + std::to_string(vertex->count) +
                   " vertices and at least " + std::to_string(needed) +
                   " bytes of data, but only " + std::to_string(body) + " bytes follow it");
}

// ---------------------------------------------------------------------------------------- PCD

namespace {

/// PCL 1.13 knows these SIZE/TYPE pairs; any other gives an unknown field type.
bool knownPcdType(u64 size, char type) {
  switch (type) {
    case 'F':
      return size == 4 || size == 8;
    case 'I':
    case 'U':
      return size == 1 || size == 2 || size == 4;
    default:
      return false;
  }
}

/// PCL sizes its buffers from the two 32-bit sizes that start a binary_compressed block (the
/// uncompressed one twice over) and decompresses from the mapped file by the compressed one:
/// both are checked against the header and the file first.
void checkCompressedBlock(const std::string& path, const std::string& where, u64 offset,
                          u64 file_size, u64 expected_bytes) {
  if (file_size < offset + 8)
    throw RunError(where + "truncated: the binary_compressed block's two sizes are missing");
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(offset));
  unsigned char b[8] = {};
  in.read(reinterpret_cast<char*>(b), 8);
  if (in.gcount() != 8)
    throw RunError(where + "truncated: the binary_compressed block's two sizes are missing");
  auto le32 = [&](int at) {
    return static_cast<u64>(b[at]) | static_cast<u64>(b[at + 1]) << 8 |
           static_cast<u64>(b[at + 2]) << 16 | static_cast<u64>(b[at + 3]) << 24;
  };
  const u64 compressed = le32(0), uncompressed = le32(4);
  const u64 available = file_size - offset - 8;
  if (compressed > available)
    throw RunError(where + "truncated: the binary_compressed block announces " +
                   std::to_string(compressed) + " compressed bytes, but only " +
                   std::to_string(available) + " follow");
  if (uncompressed != expected_bytes)
    throw RunError(where + "the binary_compressed block announces " + std::to_string(uncompressed) +
                   " uncompressed bytes where the header's points need " +
                   std::to_string(expected_bytes));
}

}  // namespace

void checkPcdHeaderText(const std::string& path, const std::string& where) {
  u64 file_size = 0;
  const std::string head = readHead(path, file_size);
  // binary_compressed data (LZF) shrinks by at most ~88×; ascii needs at least two characters
  // per value of at most 8 bytes.
  u64 factor = 4;
  std::vector<u64> sizes, counts;
  std::size_t fields = 0;
  u64 points = 0, width = 0, height = 0;
  u64 compressed_at = 0;  // offset of the binary_compressed block's two sizes
  u64 data_at = 0;        // after the last DATA line
  std::string storage;    // its word: ascii, binary, binary_compressed
  std::vector<std::string> names;
  std::string types;
  auto record = [&] {
    u64 r = 0;
    for (std::size_t i = 0; i < fields; ++i)
      r += (i < sizes.size() ? sizes[i] : 4) * (i < counts.size() ? counts[i] : 1);
    return r;
  };
  auto checkFits = [&](u64 n, const char* what) {
    const u64 bytes = saturatingMul(n, record());
    if (bytes > saturatingMul(factor, file_size))
      throw RunError(where + "the header announces " + std::to_string(n) + " " + what + " of " +
                     std::to_string(record()) + " bytes, more than a file of " +
                     std::to_string(file_size) + " bytes can hold");
  };

  // The same reading as PCL's PCDReader::readHeader: trimmed lines, keywords matched by prefix,
  // reading stops at the first line it does not know (after DATA: the data); the last DATA counts.
  std::size_t pos = 0, line_no = 0;
  while (pos < head.size()) {
    std::size_t nl = head.find('\n', pos);
    if (nl == std::string::npos)
      nl = head.size();
    const std::string line = head.substr(pos, nl - pos);
    pos = nl + 1;
    ++line_no;
    const auto t = tokens(line, " \t\r");
    if (t.empty())
      continue;
    const std::string& key = t[0];
    auto fail = [&](const std::string& what) {
      throw RunError(where + "PCD header line " + std::to_string(line_no) + ": " + what);
    };
    auto startsWith = [&](const char* prefix) { return key.rfind(prefix, 0) == 0; };
    auto values = [&](u64 max, const char* what) {
      std::vector<u64> v(t.size() - 1);
      for (std::size_t i = 1; i < t.size(); ++i)
        if (!parseCount(t[i], max, v[i - 1]))
          fail(std::string(what) + " '" + t[i] + "' is not a valid value");
      return v;
    };
    if (startsWith("#") || startsWith("VERSION"))
      continue;
    if (startsWith("FIELDS") || startsWith("COLUMNS")) {
      fields = t.size() - 1;
      names.assign(t.begin() + 1, t.end());
      sizes.clear();
      counts.clear();
      types.clear();
    } else if (startsWith("SIZE")) {
      sizes = values(8, "SIZE");
      if (sizes.size() != fields)
        fail("SIZE has " + std::to_string(sizes.size()) + " values for " + std::to_string(fields) +
             " fields");
    } else if (startsWith("TYPE")) {
      if (t.size() - 1 != fields || sizes.size() != fields)
        fail("TYPE needs one value per field, after SIZE");
      for (std::size_t i = 0; i < fields; ++i)
        if (t[i + 1].size() != 1 || !knownPcdType(sizes[i], t[i + 1][0]))
          fail("TYPE '" + t[i + 1] + "' with SIZE " + std::to_string(sizes[i]) +
               " is not a type PCL reads");
      for (std::size_t i = 0; i < fields; ++i)
        types += t[i + 1][0];
    } else if (startsWith("COUNT")) {
      counts = values(1u << 20, "COUNT");
      if (counts.size() != fields || std::count(counts.begin(), counts.end(), 0u) > 0)
        fail("COUNT needs one positive value per field");
    } else if (startsWith("WIDTH") || startsWith("HEIGHT") || startsWith("POINTS")) {
      if (t.size() != 2)
        fail("'" + key + "' needs one value");
      u64 v = 0;
      if (!parseCount(t[1], file_size, v))
        fail("the header announces an impossible number of points ('" + line + "')");
      (startsWith("WIDTH") ? width : startsWith("HEIGHT") ? height : points) = v;
      if (startsWith("POINTS"))
        checkFits(points, "points");  // PCL allocates here
    } else if (startsWith("VIEWPOINT")) {
      continue;
    } else if (startsWith("DATA")) {
      // PCL does not stop here: it reads on, and the last DATA line decides where the data start
      // and how they are stored (found by tests/fuzz: a DATA line before the fields).
      const bool compressed = t.size() >= 2 && t[1].rfind("binary_compressed", 0) == 0;
      const bool binary = t.size() >= 2 && t[1].rfind("binary", 0) == 0;
      factor = compressed ? 100 : binary ? 1 : 4;
      compressed_at = compressed ? pos : 0;
      data_at = pos;
      storage = t.size() >= 2 ? t[1] : "";
      continue;
    } else {
      break;
    }
  }
  if (saturatingMul(width, height) != 0)
    checkFits(saturatingMul(width, height), "points");
  checkFits(points, "points");
  if (compressed_at != 0)
    checkCompressedBlock(
        path, where, compressed_at, file_size,
        saturatingMul(points != 0 ? points : saturatingMul(width, height), record()));
  if (data_at != 0 && types.size() == fields) {
    std::vector<PcdField> declared(fields);
    for (std::size_t i = 0; i < fields; ++i)
      declared[i] = {names[i], types[i], i < sizes.size() ? sizes[i] : 4,
                     i < counts.size() ? counts[i] : 1};
    checkPcdData(path, data_at, storage, declared,
                 points != 0 ? points : saturatingMul(width, height), where);
  }
}

void checkPcdLayout(const pcl::PCLPointCloud2& header, const std::string& where) {
  std::uint32_t expected = 0;
  for (const auto& f : header.fields) {
    const std::size_t size = ply::datatypeBytes(f.datatype);
    if (size == 0 || f.count == 0 || f.offset != expected ||
        f.offset + size * f.count > header.point_step)
      throw RunError(where + "field '" + f.name +
                     "' does not fit its record (inconsistent size, type or count)");
    expected += static_cast<std::uint32_t>(size * f.count);
  }
  if (header.fields.empty() || expected != header.point_step)
    throw RunError(where + "the fields do not fit the record (inconsistent size, type or count)");
  // PCL sizes its buffer when it meets POINTS, with the record known by then; a SIZE or COUNT
  // line after it makes the buffer too small for what its reader then writes.
  if (header.data.size() != static_cast<std::size_t>(header.width) * header.height * expected)
    throw RunError(where +
                   "the POINTS line comes before the record layout is complete (SIZE, "
                   "TYPE and COUNT must precede it)");
}

}  // namespace slipfit::pipeline::detail
