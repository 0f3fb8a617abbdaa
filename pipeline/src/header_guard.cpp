#include "header_guard.h"

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

constexpr std::size_t kMaxHeaderBytes = 1 << 20;

/// The file's first kMaxHeaderBytes (fewer when it is shorter), and its size.
std::string readHead(const std::string& path, u64& file_size) {
  std::error_code ec;
  file_size = std::filesystem::file_size(path, ec);
  if (ec)
    file_size = 0;
  std::ifstream in(path, std::ios::binary);
  std::string head(static_cast<std::size_t>(std::min<u64>(file_size, kMaxHeaderBytes)), '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  return head;
}

std::vector<std::string> tokens(const std::string& line, const char* separators) {
  std::vector<std::string> out;
  std::size_t at = line.find_first_not_of(separators);
  while (at != std::string::npos) {
    const std::size_t end = line.find_first_of(separators, at);
    out.push_back(line.substr(at, end == std::string::npos ? std::string::npos : end - at));
    at = line.find_first_not_of(separators, end);
  }
  return out;
}

/// Fields between runs of separators, with an empty first or last field when the line starts or
/// ends with a separator (boost::split with token_compress_on, as PCL splits obj_info lines).
std::vector<std::string> splitKeepingEnds(const std::string& line, const char* separators) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while (true) {
    const std::size_t end = line.find_first_of(separators, at);
    out.push_back(line.substr(at, end == std::string::npos ? std::string::npos : end - at));
    if (end == std::string::npos)
      return out;
    at = line.find_first_not_of(separators, end);
    if (at == std::string::npos) {
      out.emplace_back();
      return out;
    }
  }
}

u64 saturatingAdd(u64 a, u64 b) {
  return a > std::numeric_limits<u64>::max() - b ? std::numeric_limits<u64>::max() : a + b;
}

u64 saturatingMul(u64 a, u64 b) {
  return b != 0 && a > std::numeric_limits<u64>::max() / b ? std::numeric_limits<u64>::max()
                                                           : a * b;
}

// ---------------------------------------------------------------------------------------- PLY

bool isUnsignedCountType(const std::string& t) {
  return t == "uchar" || t == "uint8" || t == "ushort" || t == "uint16" || t == "uint" ||
         t == "uint32";
}

struct PlyProperty {
  std::string name, type;
  bool list = false;
  std::size_t min_bytes = 0;  // binary: the scalar, or the count of an empty list
};

struct PlyElement {
  std::string name;
  u64 count = 0;
  std::vector<PlyProperty> properties;
};

/// PCL maps uchar red, green, blue (or diffuse_*) to one packed rgb field and writes it when it
/// reads blue; alpha amends that field. Any other arrangement makes it write out of place or
/// assert, so the colours must come as red, green, blue (then alpha) in a row.
void checkVertexColours(const PlyElement& vertex, const std::string& where) {
  static const char* const kColourNames[] = {"red",           "green",        "blue", "diffuse_red",
                                             "diffuse_green", "diffuse_blue", "alpha"};
  std::vector<std::size_t> at;
  std::string names;
  for (std::size_t i = 0; i < vertex.properties.size(); ++i) {
    const PlyProperty& p = vertex.properties[i];
    const bool colour = (p.type == "uchar" || p.type == "uint8") &&
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

bool parseCount(const std::string& text, std::uint64_t max, std::uint64_t& value) {
  if (text.empty() || text.size() > 19 ||
      !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return false;
  value = std::stoull(text);
  return value <= max;
}

namespace {

/// Byte size of a PLY scalar type name (both spellings), 0 when unknown.
std::size_t plyTypeSize(const std::string& t) {
  const std::optional<ply::Scalar> scalar = ply::scalarNamed(t);
  return scalar ? ply::scalarBytes(*scalar) : 0;
}

}  // namespace

namespace {

/// What checkPlyHeader reads off a PLY header, line by line as PCL's reader does.
class PlyHeaderScan {
 public:
  PlyHeaderScan(const std::string& where, u64 file_size) : where_(where), file_size_(file_size) {}

  /// Reads the header of \a head (the file's start); RunError naming the line for what PCL's
  /// reader would crash on.
  void scan(const std::string& head) {
    // PCL reads three bytes of magic, skips one, then reads the header line by line.
    std::size_t pos = 4;
    while (header_end == 0) {
      const std::size_t nl = head.find('\n', pos);
      if (nl == std::string::npos)
        throw RunError(where_ + "the PLY header has no end_header line" +
                       (head.size() == kMaxHeaderBytes ? " in its first 1 MiB" : ""));
      std::string line = head.substr(pos, nl - pos);
      pos = nl + 1;
      ++line_no_;
      if (!line.empty() && line.back() == '\r')
        line.pop_back();
      if (takeLine(line))
        header_end = pos;
    }
    if (format.empty())
      throw RunError(where_ + "the PLY header has no format line");
  }

  std::vector<PlyElement> elements;
  std::string format;
  u64 width = 0, height = 0;  // as PCL tracks them: obj_info num_cols / num_rows, then the vertex
  std::size_t header_end = 0;

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw RunError(where_ + "PLY header line " + std::to_string(line_no_) + ": " + what);
  }

  /// One header line; true at end_header.
  bool takeLine(const std::string& line) {
    if (std::any_of(line.begin(), line.end(), [](char c) {
          const auto u = static_cast<unsigned char>(c);
          return (u < 0x20 && c != '\t') || u == 0x7f;
        }))
      fail("contains a control character");
    const auto t = tokens(line, " \t");
    if (t.empty())
      return false;  // PCL ignores blank lines
    if (line[0] == ' ' || line[0] == '\t')
      fail("starts with white space");  // PCL asserts on an indented obj_info line
    const std::string& keyword = t[0];
    if (keyword == "format") {
      if (!format.empty())
        fail("a second format line");
      if (t.size() != 3 ||
          (t[1] != "ascii" && t[1] != "binary_little_endian" && t[1] != "binary_big_endian") ||
          t[2] != "1.0")
        fail("unsupported format '" + line + "'");
      format = t[1];
    } else if (keyword == "obj_info") {
      objInfo(line);
    } else if (keyword == "element") {
      element(t, line);
    } else if (keyword == "property") {
      property(t, line);
    } else if (keyword == "end_header") {
      return true;
    }
    // comment lines, and unknown keywords that PCL ignores too
    return false;
  }

  void objInfo(const std::string& line) {
    // PCL splits this line keeping an empty last token after trailing blanks, so that
    // "obj_info num_rows " sets the height to atoi("") = 0.
    const auto st = splitKeepingEnds(line, " \t");
    if (st.size() >= 3 && (st[1] == "num_cols" || st[1] == "num_rows")) {
      u64 v = 0;
      if (!parseCount(st[2], std::numeric_limits<std::int32_t>::max(), v) || v == 0)
        fail("obj_info " + st[1] + " '" + st[2] + "' is not a positive count");
      (st[1] == "num_cols" ? width : height) = v;
    }
  }

  void element(const std::vector<std::string>& t, const std::string& line) {
    u64 count = 0;
    if (t.size() != 3)
      fail("malformed element line '" + line + "'");
    if (!parseCount(t[2], file_size_, count))
      fail("'" + line + "' announces an impossible number of records for a file of " +
           std::to_string(file_size_) + " bytes");
    for (const auto& e : elements)
      if (e.name == t[1])
        fail("a second '" + t[1] + "' element");
    elements.push_back({t[1], count, {}});
    if (t[1] == "vertex" && (width == 0 || height == 0)) {
      width = count;
      height = 1;
    }
  }

  void property(const std::vector<std::string>& t, const std::string& line) {
    if (elements.empty())
      fail("a property before any element");
    PlyElement& e = elements.back();
    PlyProperty p;
    if (t.size() == 3 && plyTypeSize(t[1]) > 0) {
      p = {t[2], t[1], false, plyTypeSize(t[1])};
    } else if (t.size() == 5 && t[1] == "list" && isUnsignedCountType(t[2]) &&
               plyTypeSize(t[3]) > 0) {
      p = {t[4], t[3], true, plyTypeSize(t[2])};
    } else {
      fail("malformed property line '" + line + "'");
    }
    if (std::any_of(e.properties.begin(), e.properties.end(),
                    [&](const PlyProperty& q) { return q.name == p.name; }))
      fail("a second property '" + p.name + "' in element '" + e.name + "'");
    if (p.list && e.name == "vertex")
      fail("vertex property '" + p.name +
           "' is a list; slipfit reads scalar vertex properties only");
    e.properties.push_back(p);
  }

  const std::string& where_;
  u64 file_size_;
  std::size_t line_no_ = 1;
};

}  // namespace

void checkPlyHeader(const std::string& path, const std::string& where) {
  u64 file_size = 0;
  const std::string head = readHead(path, file_size);
  if (head.size() < 4 || head.compare(0, 3, "ply") != 0)
    throw RunError(where + "not a PLY file (it does not start with 'ply')");
  PlyHeaderScan h(where, file_size);
  h.scan(head);
  const std::vector<PlyElement>& elements = h.elements;
  const auto vertex = std::find_if(elements.begin(), elements.end(),
                                   [](const PlyElement& e) { return e.name == "vertex"; });
  if (vertex == elements.end())
    throw RunError(where + "the PLY header has no vertex element");
  checkVertexColours(*vertex, where);

  // PCL sizes its buffer by num_cols × num_rows when both are given: that grid must be the vertex
  // element or, for organized clouds, the range_grid element that maps cells to vertices.
  const u64 grid = h.width * h.height;
  if (grid != vertex->count) {
    const auto range = std::find_if(elements.begin(), elements.end(),
                                    [](const PlyElement& e) { return e.name == "range_grid"; });
    if (range == elements.end() || range->count != grid || grid < vertex->count)
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
  const u64 body = file_size - std::min<u64>(file_size, h.header_end);
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
      sizes.clear();
      counts.clear();
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
