#include "ply_rows.h"

#include "slipfit/pipeline/errors.h"

#include "ply/ply_header.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace slipfit::pipeline::tiling {

std::string plyHeader(const std::vector<StreamField>& fields, std::uint64_t count) {
  std::vector<ply::Property> properties;
  properties.reserve(fields.size());
  for (const StreamField& f : fields)
    properties.push_back({f.name, f.scalar});
  return ply::headerText("binary_little_endian", count, properties);
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
      throw RunError("'" + path_ + "': write failed (disk full?)" +
                     (n < 0 ? ": " + std::string(std::strerror(errno)) : std::string()));
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
