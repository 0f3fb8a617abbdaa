// CloudStream: the coordinates of PLY and PCD files read by row ranges equal those PCL's readers
// load from the whole file, in every encoding.

#include "slipfit/pipeline/cloud_stream.h"
#include "slipfit/pipeline/errors.h"

#include "run_cli.h"

#include <gtest/gtest.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <random>

namespace slipfit::pipeline {
namespace {

pcl::PointCloud<pcl::PointXYZRGBNormal> randomCloud(std::size_t n) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-100.0f, 100.0f);
  pcl::PointCloud<pcl::PointXYZRGBNormal> c;
  for (std::size_t i = 0; i < n; ++i) {
    pcl::PointXYZRGBNormal p;
    p.x = u(rng);
    p.y = u(rng);
    p.z = u(rng);
    p.normal_x = 1.0f;
    p.r = 7;
    c.push_back(p);
  }
  return c;
}

/// Rows [first, first + count) read from \a path equal \a cloud's, exactly.
void expectRows(CloudStream& s, const pcl::PointCloud<pcl::PointXYZRGBNormal>& cloud,
                std::uint64_t first, std::uint64_t count) {
  Eigen::Matrix3Xd xyz;
  s.read(first, count, xyz);
  ASSERT_EQ(xyz.cols(), static_cast<Eigen::Index>(count));
  for (std::uint64_t r = 0; r < count; ++r) {
    const auto& p = cloud[static_cast<std::size_t>(first + r)];
    ASSERT_EQ(xyz(0, static_cast<Eigen::Index>(r)), static_cast<double>(p.x)) << first + r;
    ASSERT_EQ(xyz(1, static_cast<Eigen::Index>(r)), static_cast<double>(p.y)) << first + r;
    ASSERT_EQ(xyz(2, static_cast<Eigen::Index>(r)), static_cast<double>(p.z)) << first + r;
  }
}

TEST(CloudStream, RowRangesEqualPclsWholeRead) {
  const auto cloud = randomCloud(5000);
  const std::string dir = testing::scratchFile("stream.keep", "");
  struct Case {
    std::string name;
    bool binary, ply;
  };
  for (const Case& c : {Case{"a.ply", false, true}, Case{"b.ply", true, true},
                        Case{"a.pcd", false, false}, Case{"b.pcd", true, false}}) {
    const std::string path = dir + "." + c.name;
    if (c.ply)
      ASSERT_EQ(pcl::io::savePLYFile(path, cloud, c.binary), 0);
    else
      ASSERT_EQ(pcl::io::savePCDFile(path, cloud, c.binary), 0);
    // What PCL reads back from the file (ascii files round through their decimal text).
    pcl::PointCloud<pcl::PointXYZRGBNormal> loaded;
    ASSERT_EQ(c.ply ? pcl::io::loadPLYFile(path, loaded) : pcl::io::loadPCDFile(path, loaded), 0);
    CloudStream s(path);
    EXPECT_EQ(s.size(), 5000u) << c.name;
    EXPECT_FALSE(s.doubleCoordinates());
    expectRows(s, loaded, 0, 1);
    // Whole rows: every field of PCL's point type, each at its place in a little-endian row.
    std::vector<char> rows;
    s.readRecords(1, 2, rows);
    ASSERT_EQ(rows.size(), 2 * s.recordBytes());
    for (const std::string name : {c.ply ? "nx" : "normal_x", "curvature"}) {
      const auto f = std::find_if(s.fields().begin(), s.fields().end(),
                                  [&](const StreamField& x) { return x.name == name; });
      ASSERT_NE(f, s.fields().end()) << c.name << " " << name;
      ASSERT_EQ(f->scalar, ply::Scalar::f32);
      float v[2];
      for (int r = 0; r < 2; ++r)
        std::memcpy(&v[r], rows.data() + r * s.recordBytes() + f->offset, 4);
      const float expected = name == "curvature" ? 0.0f : 1.0f;
      EXPECT_EQ(v[0], expected) << c.name << " " << name;
      EXPECT_EQ(v[1], expected) << c.name << " " << name;
    }
    expectRows(s, loaded, 10, 990);
    expectRows(s, loaded, 2500, 2500);
    // Binary files seek; ascii ones read again from the first row when a range lies behind
    // (a tiler's second pass): any order gives the rows.
    expectRows(s, loaded, 7, 3);
    expectRows(s, loaded, 4999, 1);
    expectRows(s, loaded, 0, 5000);
    Eigen::Matrix3Xd xyz;
    EXPECT_THROW(s.read(4990, 11, xyz), RunError) << c.name;
  }
}

/// A binary big-endian PLY of doubles at UTM-like coordinates, after a face element is declared.
TEST(CloudStream, BigEndianDoublesKeepTheirPrecision) {
  std::string text =
      "ply\nformat binary_big_endian 1.0\ncomment georeferenced\nelement vertex 3\n"
      "property double x\nproperty double y\nproperty double z\nproperty uchar intensity\n"
      "element face 0\nproperty list uchar int vertex_indices\nend_header\n";
  const double values[3][3] = {{500000.125, 5400000.0625, 12.5},
                               {500001.001, 5400001.002, 13.003},
                               {499999.999, 5399999.998, 11.997}};
  for (const auto& row : values) {
    for (const double v : row) {
      unsigned char b[8];
      std::memcpy(b, &v, 8);
      for (int k = 7; k >= 0; --k)
        text.push_back(static_cast<char>(b[k]));
    }
    text.push_back(static_cast<char>(200));
  }
  CloudStream s(testing::scratchFile("big.ply", text));
  EXPECT_TRUE(s.doubleCoordinates());
  Eigen::Matrix3Xd xyz;
  s.read(1, 2, xyz);
  for (int r = 0; r < 2; ++r)
    for (int a = 0; a < 3; ++a)
      EXPECT_EQ(xyz(a, r), values[r + 1][a]);
  // Whole rows come back little-endian: the doubles and the intensity after them.
  ASSERT_EQ(s.fields().size(), 4u);
  EXPECT_EQ(s.fields()[3].name, "intensity");
  EXPECT_EQ(s.fields()[3].scalar, ply::Scalar::u8);
  std::vector<char> rows;
  s.readRecords(0, 3, rows);
  ASSERT_EQ(rows.size(), 3u * 25u);
  for (int r = 0; r < 3; ++r) {
    double y;
    std::memcpy(&y, rows.data() + r * 25 + 8, 8);
    EXPECT_EQ(y, values[r][1]);
    EXPECT_EQ(static_cast<unsigned char>(rows[static_cast<std::size_t>(r) * 25 + 24]), 200u);
  }
}

TEST(CloudStream, AsciiRowsAreCheckedAgainstTheirTypes) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nproperty uchar intensity\nproperty int label\nend_header\n";
  std::vector<char> rows;
  CloudStream good(testing::scratchFile("types.ply", header + "1 2 3 255 -7\n4 5 6 0 2147483647\n"
                                                              "7 8 9 12 0\n"));
  good.readRecords(0, 3, rows);
  ASSERT_EQ(rows.size(), 3u * 17u);
  EXPECT_EQ(static_cast<unsigned char>(rows[12]), 255u);
  std::int32_t label;
  std::memcpy(&label, rows.data() + 13, 4);
  EXPECT_EQ(label, -7);
  std::memcpy(&label, rows.data() + 17 + 13, 4);
  EXPECT_EQ(label, 2147483647);
  for (const std::string& bad :
       {"1 2 3 256 0\n", "1 2 3 -1 0\n", "1 2 3 1.5 0\n", "1 2 3 1 2147483648\n", "1 2 x 1 0\n"}) {
    CloudStream s(testing::scratchFile("bad_types.ply", header + bad + bad + bad));
    try {
      s.readRecords(0, 1, rows);
      ADD_FAILURE() << bad << " accepted";
    } catch (const RunError& e) {
      EXPECT_NE(std::string(e.what()).find("row 0: '"), std::string::npos) << e.what();
    }
  }
}

TEST(CloudStream, RefusesWhatItCannotReadByRows) {
  const auto refused = [](const std::string& name, const std::string& text,
                          const std::string& why) {
    try {
      CloudStream s(testing::scratchFile(name, text));
      ADD_FAILURE() << name << " accepted";
    } catch (const RunError& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  };
  refused("compressed.pcd",
          "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT "
          "1\nPOINTS 1\nDATA binary_compressed\n",
          "binary_compressed cannot");
  refused("short.pcd",
          "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1000000\n"
          "HEIGHT 1\nPOINTS 1000000\nDATA binary\n0123456789AB",
          "announces 1000000 points of 12 bytes; the file holds 1");
  refused("nox.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float y\nend_header\n1\n",
          "no x, y and z");
  refused("list.ply",
          "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
          "property float z\nproperty list uchar int n\nend_header\n",
          "line 7: vertex property 'n' is a list");
  refused("before.ply",
          "ply\nformat binary_little_endian 1.0\nelement face 1\nproperty list uchar int v\n"
          "element vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
          "end_header\n0000000000000000",
          "line 4: a list property before the vertex element");
  refused("mixed.ply",
          "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty double y\n"
          "property float z\nend_header\n",
          "line 5: x, y and z must have one type");
}

}  // namespace
}  // namespace slipfit::pipeline
