#include "slipfit/pipeline/ply_scalar.h"

#include <pcl/PCLPointField.h>

#include <cerrno>
#include <charconv>
#include <cstdlib>
#include <cstring>

namespace slipfit::pipeline::ply {

namespace {

struct Entry {
  Scalar scalar;
  const char* name;
  const char* long_name;  ///< the other PLY spelling ("" for the wide integers)
  std::size_t bytes;
  std::uint8_t datatype;  ///< PCLPointField's (0 for the wide integers: PCL 1.13 has none)
};

constexpr Entry kTable[] = {
    {Scalar::i8, "char", "int8", 1, pcl::PCLPointField::INT8},
    {Scalar::u8, "uchar", "uint8", 1, pcl::PCLPointField::UINT8},
    {Scalar::i16, "short", "int16", 2, pcl::PCLPointField::INT16},
    {Scalar::u16, "ushort", "uint16", 2, pcl::PCLPointField::UINT16},
    {Scalar::i32, "int", "int32", 4, pcl::PCLPointField::INT32},
    {Scalar::u32, "uint", "uint32", 4, pcl::PCLPointField::UINT32},
    {Scalar::i64, "int64", "", 8, 0},
    {Scalar::u64, "uint64", "", 8, 0},
    {Scalar::f32, "float", "float32", 4, pcl::PCLPointField::FLOAT32},
    {Scalar::f64, "double", "float64", 8, pcl::PCLPointField::FLOAT64},
};

const Entry& entry(Scalar scalar) {
  return kTable[static_cast<std::size_t>(scalar)];
}

template <typename T>
T load(const void* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

template <typename T>
void store(void* p, double v) {
  const T t = static_cast<T>(v);
  std::memcpy(p, &t, sizeof t);
}

template <typename T>
char* printAs(const void* p, char* out, char* end) {
  // Shortest text that reads back to the same value, for floats as for integers.
  return std::to_chars(out, end, load<T>(p)).ptr;
}

/// Calls \a f with a value of the C++ type of \a scalar (its value unused: the type is what
/// counts).
template <typename F>
decltype(auto) withType(Scalar scalar, F&& f) {
  switch (scalar) {
    case Scalar::i8:
      return f(std::int8_t{});
    case Scalar::u8:
      return f(std::uint8_t{});
    case Scalar::i16:
      return f(std::int16_t{});
    case Scalar::u16:
      return f(std::uint16_t{});
    case Scalar::i32:
      return f(std::int32_t{});
    case Scalar::u32:
      return f(std::uint32_t{});
    case Scalar::i64:
      return f(std::int64_t{});
    case Scalar::u64:
      return f(std::uint64_t{});
    case Scalar::f32:
      return f(float{});
    case Scalar::f64:
      break;
  }
  return f(double{});
}

}  // namespace

std::optional<Scalar> scalarNamed(const std::string& name, bool wide) {
  for (const Entry& e : kTable)
    if (name == e.name || (*e.long_name && name == e.long_name))
      return wide || e.datatype != 0 ? std::optional<Scalar>(e.scalar) : std::nullopt;
  return std::nullopt;
}

const char* scalarName(Scalar scalar) {
  return entry(scalar).name;
}

std::size_t scalarBytes(Scalar scalar) {
  return entry(scalar).bytes;
}

bool isFloating(Scalar scalar) {
  return scalar == Scalar::f32 || scalar == Scalar::f64;
}

bool isSigned(Scalar scalar) {
  return scalar == Scalar::i8 || scalar == Scalar::i16 || scalar == Scalar::i32 ||
         scalar == Scalar::i64 || isFloating(scalar);
}

std::optional<std::uint8_t> datatypeOfScalar(Scalar scalar) {
  const std::uint8_t datatype = entry(scalar).datatype;
  return datatype ? std::optional<std::uint8_t>(datatype) : std::nullopt;
}

std::optional<Scalar> scalarOfDatatype(std::uint8_t datatype) {
  if (datatype == 0)
    return std::nullopt;
  for (const Entry& e : kTable)
    if (e.datatype == datatype)
      return e.scalar;
  return std::nullopt;
}

std::size_t datatypeBytes(std::uint8_t datatype) {
  const std::optional<Scalar> scalar = scalarOfDatatype(datatype);
  return scalar ? scalarBytes(*scalar) : 0;
}

double decode(Scalar scalar, const void* p) {
  return withType(scalar, [p](auto type) { return static_cast<double>(load<decltype(type)>(p)); });
}

void encode(Scalar scalar, double value, void* p) {
  withType(scalar, [&](auto type) { store<decltype(type)>(p, value); });
}

char* print(Scalar scalar, const void* p, char* out, char* end) {
  return withType(scalar, [&](auto type) { return printAs<decltype(type)>(p, out, end); });
}

bool parse(Scalar scalar, const std::string& text, void* out) {
  char* end = nullptr;
  if (text.empty())
    return false;
  if (isFloating(scalar)) {
    const double v = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size())
      return false;
    encode(scalar, v, out);
    return true;
  }
  errno = 0;
  if (isSigned(scalar)) {
    const long long v = std::strtoll(text.c_str(), &end, 10);
    if (end != text.c_str() + text.size() || errno)
      return false;
    return withType(scalar, [&](auto type) {
      const auto value = static_cast<decltype(type)>(v);
      if (static_cast<long long>(value) != v)
        return false;
      std::memcpy(out, &value, sizeof value);
      return true;
    });
  }
  if (text[0] == '-')
    return false;
  const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
  if (end != text.c_str() + text.size() || errno)
    return false;
  return withType(scalar, [&](auto type) {
    const auto value = static_cast<decltype(type)>(v);
    if (static_cast<unsigned long long>(value) != v)
      return false;
    std::memcpy(out, &value, sizeof value);
    return true;
  });
}

}  // namespace slipfit::pipeline::ply
