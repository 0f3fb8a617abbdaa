#include "ply_rows.h"

#include "slipfit/pipeline/errors.h"

#include <algorithm>
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

void copyFields(const std::vector<StreamField>& from, const char* source,
                const std::vector<StreamField>& to, char* target) {
  for (const StreamField& t : to) {
    const StreamField* f = findField(from, t.name);
    if (!f || f->bytes != t.bytes)
      throw std::logic_error("copyFields: no field " + t.name + " of that size");
    std::memcpy(target + t.offset, source + f->offset, t.bytes);
  }
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

double fieldValue(const StreamField& f, const char* row) {
  const char* p = row + f.offset;
  const std::string& t = f.type;
  if (t == "float")
    return load<float>(p);
  if (t == "double")
    return load<double>(p);
  if (t == "char")
    return load<std::int8_t>(p);
  if (t == "uchar")
    return load<std::uint8_t>(p);
  if (t == "short")
    return load<std::int16_t>(p);
  if (t == "ushort")
    return load<std::uint16_t>(p);
  if (t == "int")
    return load<std::int32_t>(p);
  if (t == "uint")
    return load<std::uint32_t>(p);
  if (t == "int64")
    return static_cast<double>(load<std::int64_t>(p));
  return static_cast<double>(load<std::uint64_t>(p));
}

void setFieldValue(const StreamField& f, char* row, double value) {
  char* p = row + f.offset;
  const std::string& t = f.type;
  if (t == "float")
    store<float>(p, value);
  else if (t == "double")
    store<double>(p, value);
  else if (t == "char")
    store<std::int8_t>(p, value);
  else if (t == "uchar")
    store<std::uint8_t>(p, value);
  else if (t == "short")
    store<std::int16_t>(p, value);
  else if (t == "ushort")
    store<std::uint16_t>(p, value);
  else if (t == "int")
    store<std::int32_t>(p, value);
  else if (t == "uint")
    store<std::uint32_t>(p, value);
  else if (t == "int64")
    store<std::int64_t>(p, value);
  else
    store<std::uint64_t>(p, value);
}

void writeOrFail(std::ofstream& out, const char* bytes, std::size_t size, const std::string& path) {
  if (!out.write(bytes, static_cast<std::streamsize>(size)))
    throw RunError("'" + path + "': write failed (disk full?)");
}

}  // namespace slipfit::pipeline::tiling
