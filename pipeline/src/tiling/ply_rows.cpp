#include "ply_rows.h"

#include "slipfit/pipeline/errors.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace slipfit::pipeline::tiling {

std::string plyHeader(const std::vector<StreamField>& fields, std::uint64_t count) {
  std::string text = "ply\nformat binary_little_endian 1.0\ncomment slipfit\nelement vertex " +
                     std::to_string(count) + "\n";
  for (const StreamField& f : fields) {
    std::string name = f.name;
    if (name.rfind("normal_", 0) == 0)
      name = "n" + name.substr(7);
    text += "property " + f.type + " " + name + "\n";
  }
  return text + "end_header\n";
}

std::vector<StreamField> withoutFields(const std::vector<StreamField>& all,
                                       const std::vector<std::string>& drop) {
  std::vector<StreamField> kept;
  std::uint64_t offset = 0;
  for (StreamField f : all) {
    if (std::find(drop.begin(), drop.end(), f.name) != drop.end())
      continue;
    f.offset = offset;
    offset += f.bytes;
    kept.push_back(f);
  }
  return kept;
}

const StreamField* findField(const std::vector<StreamField>& fields, const std::string& name) {
  for (const StreamField& f : fields)
    if (f.name == name)
      return &f;
  return nullptr;
}

RowCopy::RowCopy(const std::vector<StreamField>& from, const std::vector<StreamField>& to) {
  for (const StreamField& t : to) {
    const StreamField* f = findField(from, t.name);
    if (!f || f->bytes != t.bytes)
      throw std::logic_error("RowCopy: no field " + t.name + " of that size");
    if (!spans_.empty() && spans_.back().from + spans_.back().bytes == f->offset &&
        spans_.back().to + spans_.back().bytes == t.offset)
      spans_.back().bytes += t.bytes;  // adjacent in both rows: one copy
    else
      spans_.push_back({f->offset, t.offset, t.bytes});
  }
}

void RowCopy::apply(const char* source, char* target) const {
  for (const Span& s : spans_)
    std::memcpy(target + s.to, source + s.from, s.bytes);
}

namespace {
template <typename T>
T load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
template <typename T>
void store(char* p, double v) {
  const T t = static_cast<T>(v);
  std::memcpy(p, &t, sizeof t);
}
}  // namespace

FieldAt fieldAt(const StreamField& f) {
  static const std::pair<const char*, ValueKind> kKinds[] = {
      {"char", ValueKind::i8},    {"uchar", ValueKind::u8},   {"short", ValueKind::i16},
      {"ushort", ValueKind::u16}, {"int", ValueKind::i32},    {"uint", ValueKind::u32},
      {"int64", ValueKind::i64},  {"uint64", ValueKind::u64}, {"float", ValueKind::f32},
      {"double", ValueKind::f64}};
  for (const auto& [name, kind] : kKinds)
    if (f.type == name)
      return {kind, f.offset};
  throw std::invalid_argument("field " + f.name + " has type " + f.type);
}

double FieldAt::get(const char* row) const {
  const char* p = row + offset;
  switch (kind) {
    case ValueKind::i8:
      return load<std::int8_t>(p);
    case ValueKind::u8:
      return load<std::uint8_t>(p);
    case ValueKind::i16:
      return load<std::int16_t>(p);
    case ValueKind::u16:
      return load<std::uint16_t>(p);
    case ValueKind::i32:
      return load<std::int32_t>(p);
    case ValueKind::u32:
      return load<std::uint32_t>(p);
    case ValueKind::i64:
      return static_cast<double>(load<std::int64_t>(p));
    case ValueKind::u64:
      return static_cast<double>(load<std::uint64_t>(p));
    case ValueKind::f32:
      return load<float>(p);
    case ValueKind::f64:
      return load<double>(p);
  }
  return 0.0;
}

void FieldAt::set(char* row, double value) const {
  char* p = row + offset;
  switch (kind) {
    case ValueKind::i8:
      return store<std::int8_t>(p, value);
    case ValueKind::u8:
      return store<std::uint8_t>(p, value);
    case ValueKind::i16:
      return store<std::int16_t>(p, value);
    case ValueKind::u16:
      return store<std::uint16_t>(p, value);
    case ValueKind::i32:
      return store<std::int32_t>(p, value);
    case ValueKind::u32:
      return store<std::uint32_t>(p, value);
    case ValueKind::i64:
      return store<std::int64_t>(p, value);
    case ValueKind::u64:
      return store<std::uint64_t>(p, value);
    case ValueKind::f32:
      return store<float>(p, value);
    case ValueKind::f64:
      return store<double>(p, value);
  }
}

void writeOrFail(std::ofstream& out, const char* bytes, std::size_t size, const std::string& path) {
  if (!out.write(bytes, static_cast<std::streamsize>(size)))
    throw RunError("'" + path + "': write failed (disk full?)");
}

PositionalFile::PositionalFile(const std::string& path) : path_(path) {
  fd_ = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd_ < 0)
    throw RunError("'" + path + "': cannot be opened for writing (" + std::strerror(errno) + ")");
}

PositionalFile::~PositionalFile() {
  if (fd_ >= 0)
    ::close(fd_);
}

void PositionalFile::write(std::uint64_t offset, const char* bytes, std::size_t size) const {
  while (size > 0) {
    const ssize_t n = ::pwrite(fd_, bytes, size, static_cast<off_t>(offset));
    if (n < 0 && errno == EINTR)
      continue;
    if (n <= 0)
      throw RunError("'" + path_ + "': write failed (" +
                     (n < 0 ? std::string(std::strerror(errno)) : "disk full?") + ")");
    bytes += n;
    size -= static_cast<std::size_t>(n);
    offset += static_cast<std::uint64_t>(n);
  }
}

void PositionalFile::close() {
  const int fd = fd_;
  fd_ = -1;
  if (fd >= 0 && ::close(fd) != 0)
    throw RunError("'" + path_ + "': write failed (" + std::strerror(errno) + ")");
}

}  // namespace slipfit::pipeline::tiling
