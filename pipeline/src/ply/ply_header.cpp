#include "ply_header.h"

#include "slipfit/pipeline/errors.h"

#include "header_text.h"

#include <algorithm>
#include <limits>
#include <optional>

namespace slipfit::pipeline::ply {

std::string headerText(const char* format, std::uint64_t count,
                       const std::vector<Property>& properties) {
  std::string text = std::string("ply\nformat ") + format +
                     " 1.0\ncomment slipfit\nelement vertex " + std::to_string(count) + "\n";
  for (const Property& p : properties) {
    std::string name = p.name;
    if (name.rfind("normal_", 0) == 0)
      name = "n" + name.substr(7);
    text += std::string("property ") + scalarName(p.scalar) + " " + name + "\n";
  }
  return text + "end_header\n";
}

const HeaderElement* Header::element(const std::string& name) const {
  for (const HeaderElement& e : elements)
    if (e.name == name)
      return &e;
  return nullptr;
}

namespace {

using u64 = std::uint64_t;
using detail::kMaxHeaderBytes;
using detail::parseCount;
using detail::splitKeepingEnds;
using detail::tokens;

/// Reads a PLY header line by line as PCL's reader does.
class HeaderScan {
 public:
  HeaderScan(const std::string& where, u64 file_size) : where_(where), file_size_(file_size) {}

  /// Reads the header of \a head (the file's start); RunError naming the line for what PCL's
  /// reader would crash on.
  void scan(const std::string& head) {
    // PCL reads three bytes of magic, skips one, then reads the header line by line.
    std::size_t pos = 4;
    while (header.end == 0) {
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
        header.end = pos;
    }
    if (header.format.empty())
      throw RunError(where_ + "the PLY header has no format line");
  }

  Header header;

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
      if (!header.format.empty())
        fail("a second format line");
      if (t.size() != 3 ||
          (t[1] != "ascii" && t[1] != "binary_little_endian" && t[1] != "binary_big_endian") ||
          t[2] != "1.0")
        fail("unsupported format '" + line + "'");
      header.format = t[1];
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
      (st[1] == "num_cols" ? header.width : header.height) = v;
    }
  }

  void element(const std::vector<std::string>& t, const std::string& line) {
    u64 count = 0;
    if (t.size() != 3)
      fail("malformed element line '" + line + "'");
    if (!parseCount(t[2], file_size_, count))
      fail("'" + line + "' announces an impossible number of records for a file of " +
           std::to_string(file_size_) + " bytes");
    for (const auto& e : header.elements)
      if (e.name == t[1])
        fail("a second '" + t[1] + "' element");
    header.elements.push_back({t[1], count, {}});
    if (t[1] == "vertex" && (header.width == 0 || header.height == 0)) {
      header.width = count;
      header.height = 1;
    }
  }

  /// The property of a "property TYPE NAME" or "property list COUNT ITEM NAME" line (COUNT an
  /// unsigned integer type); false for anything else.
  bool propertyOf(const std::vector<std::string>& t, HeaderProperty& p) const {
    if (t.size() == 3) {
      const std::optional<Scalar> scalar = scalarNamed(t[1]);
      if (!scalar)
        return false;
      p = {t[2], *scalar, false, scalarBytes(*scalar), line_no_};
      return true;
    }
    if (t.size() != 5 || t[1] != "list")
      return false;
    const std::optional<Scalar> count = scalarNamed(t[2]), item = scalarNamed(t[3]);
    if (!count || !item || isSigned(*count))
      return false;
    p = {t[4], *item, true, scalarBytes(*count), line_no_};
    return true;
  }

  void property(const std::vector<std::string>& t, const std::string& line) {
    if (header.elements.empty())
      fail("a property before any element");
    HeaderElement& e = header.elements.back();
    HeaderProperty p;
    if (!propertyOf(t, p))
      fail("malformed property line '" + line + "'");
    if (std::any_of(e.properties.begin(), e.properties.end(),
                    [&](const HeaderProperty& q) { return q.name == p.name; }))
      fail("a second property '" + p.name + "' in element '" + e.name + "'");
    if (p.list && e.name == "vertex")
      fail("vertex property '" + p.name +
           "' is a list; slipfit reads scalar vertex properties only");
    e.properties.push_back(p);
  }

  const std::string& where_;
  u64 file_size_;
  int line_no_ = 1;
};

}  // namespace

Header parseHeader(const std::string& head, std::uint64_t file_size, const std::string& where) {
  HeaderScan scan(where, file_size);
  scan.scan(head);
  return std::move(scan.header);
}

}  // namespace slipfit::pipeline::ply
