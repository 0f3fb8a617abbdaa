#include "data_guard.h"
#include "header_text.h"
#include "ply/ply_header.h"

#include "slipfit/pipeline/errors.h"
#include "slipfit/pipeline/ply_scalar.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <optional>
#include <vector>

namespace slipfit::pipeline::detail {

namespace {

using u64 = std::uint64_t;

/// The type a PCD field's TYPE and SIZE name.
ply::Scalar pcdScalar(const PcdField& f) {
  if (f.type == 'F')
    return f.size == 8 ? ply::Scalar::f64 : ply::Scalar::f32;
  const bool is_signed = f.type == 'I';
  switch (f.size) {
    case 1:
      return is_signed ? ply::Scalar::i8 : ply::Scalar::u8;
    case 2:
      return is_signed ? ply::Scalar::i16 : ply::Scalar::u16;
    case 4:
      return is_signed ? ply::Scalar::i32 : ply::Scalar::u32;
    default:
      return is_signed ? ply::Scalar::i64 : ply::Scalar::u64;
  }
}

/// Reads the data lines of a file, numbered as lines of the whole file.
class DataLines {
 public:
  DataLines(const std::string& path, u64 data_at, const std::string& where)
      : in_(path, std::ios::binary), where_(where) {
    // The header's own lines, for the numbering.
    std::string head(static_cast<std::size_t>(data_at), '\0');
    in_.read(head.data(), static_cast<std::streamsize>(data_at));
    line_ = static_cast<u64>(std::count(head.begin(), head.end(), '\n'));
  }
  /// The next line (without its end); false at the end of the file.
  bool next(std::string& text) {
    if (!std::getline(in_, text))
      return false;
    if (!text.empty() && text.back() == '\r')
      text.pop_back();
    ++line_;
    return true;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw RunError(where_ + "line " + std::to_string(line_) + ": " + what);
  }
  /// Fails unless only blank lines are left; \a rows and \a what say what the header announced.
  void expectEnd(u64 rows, const std::string& what) {
    for (std::string text; next(text);)
      if (text.find_first_not_of(" \t") != std::string::npos)
        fail("a row after the " + std::to_string(rows) + " " + what +
             " the header announces (fix the count or the data)");
  }

 private:
  std::ifstream in_;
  std::string where_;
  u64 line_ = 0;
};

/// Checks one value \a text of type \a scalar (integers only: floats read as NaN when not
/// numbers); \a what names it for the message.
void checkValue(DataLines& lines, ply::Scalar scalar, const std::string& text,
                const std::string& what) {
  if (ply::isFloating(scalar))
    return;
  unsigned char value[8];
  if (!ply::parse(scalar, text, value))
    lines.fail(what + " is '" + text + "', not a whole number a " + ply::scalarName(scalar) +
               " holds");
}

/// The most zero bytes PCL's PCD writer leaves after a binary PCD's data.
constexpr u64 kPclPadding = 4096;

/// The binary data's end must be the file's end, but for up to \a zeros zero bytes after it.
void checkNoTrailingBytes(const std::string& path, u64 data_end, const std::string& where,
                          const std::string& what, u64 zeros = 0) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  const auto size = static_cast<u64>(in.tellg());
  if (!in || size <= data_end)
    return;
  if (size - data_end <= zeros) {
    std::vector<char> tail(static_cast<std::size_t>(size - data_end));
    in.seekg(static_cast<std::streamoff>(data_end));
    if (in.read(tail.data(), static_cast<std::streamsize>(tail.size())) &&
        std::all_of(tail.begin(), tail.end(), [](char c) { return c == 0; }))
      return;
  }
  throw RunError(where + std::to_string(size - data_end) + " bytes follow the " + what +
                 " the header announces (fix the count or the data)");
}

}  // namespace

void checkPlyData(const std::string& path, const std::string& where) {
  u64 file_size = 0;
  const std::string head = readHead(path, file_size);
  const ply::Header h = ply::parseHeader(head, file_size, where);
  if (h.format != "ascii") {
    // Only a file of scalar properties has a known end (lists make records of varying size).
    u64 end = h.end;
    for (const ply::HeaderElement& e : h.elements) {
      u64 record = 0;
      for (const ply::HeaderProperty& p : e.properties) {
        if (p.list)
          return;
        record += ply::scalarBytes(p.scalar);
      }
      end += record * e.count;
    }
    checkNoTrailingBytes(
        path, end, where,
        std::to_string(h.elements.back().count) + " " + h.elements.back().name + " records");
    return;
  }
  DataLines lines(path, h.end, where);
  std::string text;
  for (const ply::HeaderElement& e : h.elements) {
    std::size_t scalars = 0;
    for (const ply::HeaderProperty& p : e.properties)
      scalars += p.list ? 0 : 1;
    for (u64 row = 0; row < e.count; ++row) {
      if (!lines.next(text))
        return;  // cut short: the reader says how (truncated)
      const std::vector<std::string> values = tokens(text, " \t");
      std::size_t at = 0;
      const auto fail_count = [&] {
        lines.fail(e.name + " " + std::to_string(row) + " has " + std::to_string(values.size()) +
                   " values where the header declares " +
                   (scalars == e.properties.size() ? std::to_string(scalars) : "others"));
      };
      for (const ply::HeaderProperty& p : e.properties) {
        if (at >= values.size())
          fail_count();
        if (!p.list) {
          checkValue(lines, p.scalar, values[at++],
                     e.name + " " + std::to_string(row) + "'s " + p.name);
          continue;
        }
        u64 items = 0;
        if (!parseCount(values[at++], values.size(), items))
          lines.fail(e.name + " " + std::to_string(row) + "'s list " + p.name + " has count '" +
                     values[at - 1] + "'");
        for (u64 k = 0; k < items; ++k) {
          if (at >= values.size())
            fail_count();
          checkValue(lines, p.scalar, values[at++],
                     e.name + " " + std::to_string(row) + "'s " + p.name + " item");
        }
      }
      if (at != values.size())
        fail_count();
    }
  }
  lines.expectEnd(h.elements.empty() ? 0 : h.elements.back().count,
                  h.elements.empty() ? "rows" : h.elements.back().name + " rows");
}

void checkPcdData(const std::string& path, u64 data_at, const std::string& storage,
                  const std::vector<PcdField>& fields, u64 points, const std::string& where) {
  u64 record = 0, values_per_row = 0;
  for (const PcdField& f : fields) {
    record += f.size * f.count;
    values_per_row += f.count;
  }
  if (storage == "binary") {
    // PCL 1.13's PCDWriter::writeBinary of a PCLPointCloud2 leaves a page of zeros (4096 bytes
    // less the header's) after the data: a file PCL wrote is read.
    checkNoTrailingBytes(path, data_at + record * points, where, std::to_string(points) + " points",
                         kPclPadding);
    return;
  }
  if (storage != "ascii")
    return;
  DataLines lines(path, data_at, where);
  std::string text;
  for (u64 row = 0; row < points;) {
    if (!lines.next(text))
      return;  // cut short: the reader says how
    const std::vector<std::string> values = tokens(text, " \t");
    if (values.empty())
      continue;  // PCL skips blank lines
    if (values.size() != values_per_row)
      lines.fail("point " + std::to_string(row) + " has " + std::to_string(values.size()) +
                 " values where the header declares " + std::to_string(values_per_row));
    std::size_t at = 0;
    for (std::size_t k = 0; k < fields.size(); ++k)
      for (u64 c = 0; c < fields[k].count; ++c)
        checkValue(lines, pcdScalar(fields[k]), values[at++],
                   "point " + std::to_string(row) + "'s " + fields[k].name);
    ++row;
  }
  lines.expectEnd(points, "points");
}

}  // namespace slipfit::pipeline::detail
