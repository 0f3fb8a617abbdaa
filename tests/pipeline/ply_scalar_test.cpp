// The PLY scalar table every reader and writer shares (ply_scalar.h): names in both spellings,
// sizes, PCL datatypes, and values through bytes and text without loss.
#include "slipfit/pipeline/ply_scalar.h"

#include <pcl/PCLPointField.h>

#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <string>

namespace slipfit::pipeline::ply {
namespace {

constexpr Scalar kAll[] = {Scalar::i8,  Scalar::u8,  Scalar::i16, Scalar::u16, Scalar::i32,
                           Scalar::u32, Scalar::i64, Scalar::u64, Scalar::f32, Scalar::f64};

TEST(PlyScalar, NamesSizesAndDatatypesAgree) {
  const std::pair<const char*, std::size_t> long_names[] = {
      {"int8", 1},  {"uint8", 1},  {"int16", 2},   {"uint16", 2},
      {"int32", 4}, {"uint32", 4}, {"float32", 4}, {"float64", 8}};
  for (const auto& [name, bytes] : long_names) {
    const auto scalar = scalarNamed(name);
    ASSERT_TRUE(scalar) << name;
    EXPECT_EQ(scalarBytes(*scalar), bytes) << name;
    EXPECT_EQ(scalarNamed(scalarName(*scalar)), scalar) << name;  // the short spelling
  }
  for (Scalar s : kAll) {
    const bool wide = s == Scalar::i64 || s == Scalar::u64;
    EXPECT_EQ(scalarNamed(scalarName(s), true), s);
    // int64 and uint64 are no PLY types: only rows streamed from a PCD carry them.
    EXPECT_EQ(scalarNamed(scalarName(s)).has_value(), !wide) << scalarName(s);
  }
  EXPECT_FALSE(scalarNamed("list"));
  EXPECT_FALSE(scalarNamed("Float"));
  using F = pcl::PCLPointField;
  const std::pair<std::uint8_t, Scalar> datatypes[] = {
      {F::INT8, Scalar::i8},     {F::UINT8, Scalar::u8},   {F::INT16, Scalar::i16},
      {F::UINT16, Scalar::u16},  {F::INT32, Scalar::i32},  {F::UINT32, Scalar::u32},
      {F::FLOAT32, Scalar::f32}, {F::FLOAT64, Scalar::f64}};
  for (const auto& [datatype, scalar] : datatypes) {
    EXPECT_EQ(scalarOfDatatype(datatype), scalar);
    EXPECT_EQ(datatypeBytes(datatype), scalarBytes(scalar));
  }
  EXPECT_FALSE(scalarOfDatatype(0));
  EXPECT_FALSE(scalarOfDatatype(200));
  EXPECT_EQ(datatypeBytes(200), 0u);
}

// Each type's extremes and a fractional value go through bytes (encode/decode) and through the
// shortest text (print/parse) and come back bit for bit; values outside a type are refused.
TEST(PlyScalar, ValuesRoundTripThroughBytesAndText) {
  const auto through = [](Scalar s, double v) {
    unsigned char bytes[8] = {}, back[8] = {};
    encode(s, v, bytes);
    char text[64];
    const std::string printed(text, print(s, bytes, text, text + sizeof text));
    EXPECT_TRUE(parse(s, printed, back)) << scalarName(s) << " '" << printed << "'";
    EXPECT_EQ(std::memcmp(bytes, back, scalarBytes(s)), 0) << scalarName(s) << " " << printed;
    return decode(s, bytes);
  };
  EXPECT_EQ(through(Scalar::i8, -128), -128);
  EXPECT_EQ(through(Scalar::u8, 255), 255);
  EXPECT_EQ(through(Scalar::i16, -32768), -32768);
  EXPECT_EQ(through(Scalar::u16, 65535), 65535);
  EXPECT_EQ(through(Scalar::i32, -2147483648.0), -2147483648.0);
  EXPECT_EQ(through(Scalar::u32, 4294967295.0), 4294967295.0);
  EXPECT_EQ(through(Scalar::i64, -9007199254740992.0), -9007199254740992.0);
  EXPECT_EQ(through(Scalar::u64, 9007199254740992.0), 9007199254740992.0);
  EXPECT_EQ(through(Scalar::f32, 0.1), static_cast<double>(0.1f));
  EXPECT_EQ(through(Scalar::f64, 0.1), 0.1);
  EXPECT_EQ(through(Scalar::f64, 5400000.123456789), 5400000.123456789);
  EXPECT_EQ(through(Scalar::i32, -7.9), -7.0);  // an integer takes the value toward zero

  unsigned char out[8];
  EXPECT_FALSE(parse(Scalar::u8, "256", out));
  EXPECT_FALSE(parse(Scalar::i8, "-129", out));
  EXPECT_FALSE(parse(Scalar::u32, "-1", out));
  EXPECT_FALSE(parse(Scalar::i32, "1.5", out));
  EXPECT_FALSE(parse(Scalar::f32, "1.5x", out));
  EXPECT_FALSE(parse(Scalar::f64, "", out));
  EXPECT_TRUE(parse(Scalar::f64, "-1e300", out));
  EXPECT_EQ(decode(Scalar::f64, out), -1e300);
}

}  // namespace
}  // namespace slipfit::pipeline::ply
