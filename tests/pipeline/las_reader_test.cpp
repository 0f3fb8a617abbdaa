// LAS input (issue 38): files written here byte by byte from the ASPRS LAS 1.4 (R15)
// specification's tables — a LAS 1.2 file of record format 1 and a LAS 1.4 file of format 7 —
// read back field by field; georeferenced coordinates through the global shift; a scene as LAS
// segmented as the same scene as PLY; and the bad files refused in one line.
#include "las/las_writer.h"
#include "run_cli.h"
#include "slipfit/pipeline/cloud_io.h"
#include "slipfit/pipeline/errors.h"
#include "tiling/segments_las.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

namespace slipfit::testing {
namespace {

using ::testing::HasSubstr;

struct LasPoint {
  std::int32_t x, y, z;
  std::uint16_t intensity;
  int return_number, returns, classification, flags, channel, direction, edge;
  int scan_angle, user_data;
  std::uint16_t source;
  double gps;
  std::uint16_t rgb[3];
};

template <typename T>
void put(std::vector<std::uint8_t>& b, std::size_t at, T v) {
  if (b.size() < at + sizeof v)
    b.resize(at + sizeof v);
  std::memcpy(b.data() + at, &v, sizeof v);
}

/// A LAS 1.\a minor file of record \a format (1, 6 or 7) holding \a points.
std::vector<std::uint8_t> lasFile(int minor, int format, const std::vector<LasPoint>& points,
                                  const double scale[3], const double offset[3]) {
  const std::uint16_t header = minor == 4 ? 375 : 227;
  const std::uint16_t record = format == 1 ? 28 : format == 6 ? 30 : 36;
  std::vector<std::uint8_t> b(header, 0);
  std::memcpy(b.data(), "LASF", 4);
  b[24] = 1;
  b[25] = static_cast<std::uint8_t>(minor);
  put<std::uint16_t>(b, 94, header);
  put<std::uint32_t>(b, 96, header);  // no VLR: the points follow the header
  b[104] = static_cast<std::uint8_t>(format);
  put<std::uint16_t>(b, 105, record);
  const auto n = static_cast<std::uint32_t>(points.size());
  put<std::uint32_t>(b, 107, format < 6 ? n : 0);
  for (int a = 0; a < 3; ++a) {
    put<double>(b, 131 + 8 * static_cast<std::size_t>(a), scale[a]);
    put<double>(b, 155 + 8 * static_cast<std::size_t>(a), offset[a]);
  }
  if (minor == 4)
    put<std::uint64_t>(b, 247, n);
  for (const LasPoint& p : points) {
    const std::size_t at = b.size();
    put(b, at + 0, p.x);
    put(b, at + 4, p.y);
    put(b, at + 8, p.z);
    put(b, at + 12, p.intensity);
    if (format == 1) {
      b.push_back(0), b.push_back(0);  // grow to the fields below
      b[at + 14] = static_cast<std::uint8_t>(p.return_number | p.returns << 3 | p.direction << 6 |
                                             p.edge << 7);
      b[at + 15] = static_cast<std::uint8_t>(p.classification | p.flags << 5);
      put<std::int8_t>(b, at + 16, static_cast<std::int8_t>(p.scan_angle));
      put<std::uint8_t>(b, at + 17, static_cast<std::uint8_t>(p.user_data));
      put<std::uint16_t>(b, at + 18, p.source);
      put<double>(b, at + 20, p.gps);
    } else {
      put<std::uint8_t>(b, at + 14, static_cast<std::uint8_t>(p.return_number | p.returns << 4));
      put<std::uint8_t>(
          b, at + 15,
          static_cast<std::uint8_t>(p.flags | p.channel << 4 | p.direction << 6 | p.edge << 7));
      put<std::uint8_t>(b, at + 16, static_cast<std::uint8_t>(p.classification));
      put<std::uint8_t>(b, at + 17, static_cast<std::uint8_t>(p.user_data));
      put<std::int16_t>(b, at + 18, static_cast<std::int16_t>(p.scan_angle));
      put<std::uint16_t>(b, at + 20, p.source);
      put<double>(b, at + 22, p.gps);
      if (format == 7)
        for (std::size_t c = 0; c < 3; ++c)
          put<std::uint16_t>(b, at + 30 + 2 * c, p.rgb[c]);
    }
    b.resize(at + record);
  }
  return b;
}

std::string writeFile(const std::string& name, const std::vector<std::uint8_t>& bytes) {
  const std::string path = scratchDir("las") + "_" + name;
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  return path;
}

std::vector<LasPoint> threePoints() {
  return {{1000, -2000, 300, 17, 1, 2, 2, 1, 0, 1, 0, -12, 5, 42, 1.5e8, {100, 200, 300}},
          {-7, 8, -9, 65535, 2, 2, 6, 0, 3, 0, 1, 30, 0, 7, 2.25, {65535, 0, 1}},
          {0, 0, 0, 0, 1, 1, 31, 4, 1, 1, 1, 0, 255, 65535, 0.0, {1, 2, 3}}};
}

double field(const pipeline::PointData& d, const std::string& name, std::size_t i) {
  const std::vector<double> v = d.numericField(name);
  EXPECT_EQ(v.size(), d.size()) << name;
  return i < v.size() ? v[i] : std::nan("");
}

TEST(LasReader, Las12Format1FieldsReadBackAsWritten) {
  const double scale[3] = {0.01, 0.01, 0.001}, offset[3] = {10.0, 20.0, -5.0};
  const std::vector<LasPoint> pts = threePoints();
  const std::string path = writeFile("f1.las", lasFile(2, 1, pts, scale, offset));
  const pipeline::PointData d = pipeline::readCloud(path, pipeline::NanPolicy::error);
  ASSERT_EQ(d.size(), 3u);
  EXPECT_FALSE(d.has_normals);
  for (std::size_t i = 0; i < 3; ++i) {
    const LasPoint& p = pts[i];
    // Coordinates: record × scale + offset, in float (the cloud's type) to its rounding.
    EXPECT_FLOAT_EQ(d.cloud->points[i].x, static_cast<float>(offset[0] + scale[0] * p.x));
    EXPECT_FLOAT_EQ(d.cloud->points[i].y, static_cast<float>(offset[1] + scale[1] * p.y));
    EXPECT_FLOAT_EQ(d.cloud->points[i].z, static_cast<float>(offset[2] + scale[2] * p.z));
    EXPECT_EQ(field(d, "intensity", i), p.intensity);
    EXPECT_EQ(field(d, "return_number", i), p.return_number);
    EXPECT_EQ(field(d, "number_of_returns", i), p.returns);
    EXPECT_EQ(field(d, "classification", i), p.classification);
    EXPECT_EQ(field(d, "classification_flags", i), p.flags);
    EXPECT_EQ(field(d, "scan_direction_flag", i), p.direction);
    EXPECT_EQ(field(d, "edge_of_flight_line", i), p.edge);
    EXPECT_EQ(field(d, "scan_angle_rank", i), p.scan_angle);
    EXPECT_EQ(field(d, "user_data", i), p.user_data);
    EXPECT_EQ(field(d, "point_source_id", i), p.source);
    EXPECT_EQ(field(d, "gps_time", i), p.gps);
  }
  EXPECT_TRUE(d.numericField("red").empty());  // format 1 has no colour
}

TEST(LasReader, Las14Format7FieldsAndColoursReadBackAsWritten) {
  const double scale[3] = {0.001, 0.001, 0.001}, offset[3] = {0.0, 0.0, 0.0};
  const std::vector<LasPoint> pts = threePoints();
  const std::string path = writeFile("f7.las", lasFile(4, 7, pts, scale, offset));
  const pipeline::PointData d = pipeline::readCloud(path, pipeline::NanPolicy::error);
  ASSERT_EQ(d.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    const LasPoint& p = pts[i];
    EXPECT_FLOAT_EQ(d.cloud->points[i].x, static_cast<float>(0.001 * p.x));
    EXPECT_EQ(field(d, "return_number", i), p.return_number);
    EXPECT_EQ(field(d, "number_of_returns", i), p.returns);
    EXPECT_EQ(field(d, "classification", i), p.classification);
    EXPECT_EQ(field(d, "classification_flags", i), p.flags);
    EXPECT_EQ(field(d, "scanner_channel", i), p.channel);
    EXPECT_EQ(field(d, "scan_direction_flag", i), p.direction);
    EXPECT_EQ(field(d, "edge_of_flight_line", i), p.edge);
    EXPECT_EQ(field(d, "scan_angle", i), p.scan_angle);
    EXPECT_EQ(field(d, "point_source_id", i), p.source);
    EXPECT_EQ(field(d, "gps_time", i), p.gps);
    EXPECT_EQ(field(d, "red", i), p.rgb[0]);
    EXPECT_EQ(field(d, "green", i), p.rgb[1]);
    EXPECT_EQ(field(d, "blue", i), p.rgb[2]);
  }
}

// Georeferenced LiDAR (UTM: x 5e5, y 5.4e6 at millimetres): the coordinates are doubles and
// lose the global shift, so the float cloud keeps their millimetres; the outputs are written in
// the file's frame, as doubles.
TEST(LasReader, GeoreferencedCoordinatesKeepTheirMillimetres) {
  const double scale[3] = {0.001, 0.001, 0.001}, offset[3] = {500000.0, 5400000.0, 0.0};
  std::vector<LasPoint> pts = threePoints();
  const std::string path = writeFile("utm.las", lasFile(2, 1, pts, scale, offset));
  const pipeline::PointData d = pipeline::readCloud(path, pipeline::NanPolicy::error);
  ASSERT_TRUE(d.frame.double_coordinates);
  for (std::size_t i = 0; i < 3; ++i) {
    const double x = d.cloud->points[i].x + d.frame.shift.x();
    const double y = d.cloud->points[i].y + d.frame.shift.y();
    EXPECT_NEAR(x, offset[0] + scale[0] * pts[i].x, 1e-4);  // float's step at 1e1-1e2: 4e-6-8e-6
    EXPECT_NEAR(y, offset[1] + scale[1] * pts[i].y, 1e-4);
  }
}

TEST(LasReader, BadFilesAreRefusedInOneLine) {
  const double scale[3] = {0.01, 0.01, 0.01}, offset[3] = {0, 0, 0};
  const std::vector<std::uint8_t> good = lasFile(2, 1, threePoints(), scale, offset);
  const auto refused = [&](const std::string& name, std::vector<std::uint8_t> bytes) {
    const std::string path = writeFile(name, bytes);
    try {
      pipeline::readCloud(path, pipeline::NanPolicy::error);
    } catch (const pipeline::RunError& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
      EXPECT_THAT(e.what(), HasSubstr(path)) << name;
      return std::string(e.what());
    }
    ADD_FAILURE() << name << " was read";
    return std::string();
  };
  std::vector<std::uint8_t> b = good;
  b.resize(b.size() - 5);
  EXPECT_THAT(refused("truncated.las", b), HasSubstr("truncated: the header announces 3 points"));
  b = good;
  b[104] = 0x81;  // LAZ sets the top bits of the format byte
  EXPECT_THAT(refused("laz_bits.las", b), HasSubstr("compressed LAS (LAZ"));
  EXPECT_THAT(refused("file.laz", good), HasSubstr("decompress it first"));
  b = good;
  b[104] = 11;
  EXPECT_THAT(refused("format.las", b), HasSubstr("point data record format 11"));
  b = good;
  put<std::uint16_t>(b, 105, 20);  // shorter than format 1's 28 bytes
  EXPECT_THAT(refused("record.las", b), HasSubstr("point records of 20 bytes, under the 28"));
  b = good;
  put<double>(b, 131, 0.0);
  EXPECT_THAT(refused("scale.las", b), HasSubstr("scale or offset of x is zero or not finite"));
  b = good;
  b[25] = 5;
  EXPECT_THAT(refused("version.las", b), HasSubstr("LAS version 1.5"));
  b = good;
  put<std::uint32_t>(b, 107, 4000000000u);  // far more points than the file holds
  EXPECT_THAT(refused("count.las", b), HasSubstr("truncated"));
  b = good;
  b[0] = 'X';
  EXPECT_THAT(refused("magic.las", b), HasSubstr("not a LAS file"));
  b.assign(good.begin(), good.begin() + 100);
  EXPECT_THAT(refused("header.las", b), HasSubstr("truncated LAS header"));
}

// The shipped scene written as LAS 1.4 format 7 at 0.1 mm (its coordinates rounded to the LAS
// grid) and the points read from it written as PLY (double coordinates and every LAS field): the
// untiled runs give the same segments.ply and primitives.yaml, and so do the tiled runs (tiles cut
// from the LAS by the streaming reader); the labels of the LAS run equal those of a float PLY of
// the rounded points.
TEST(LasReader, ASceneAsLasIsSegmentedAsTheSamePointsAsPlyTiledOrNot) {
  const pipeline::PointData scene = pipeline::readCloud(
      std::string(kSourceDir) + "/sample_clouds/scene.ply", pipeline::NanPolicy::error);
  const double scale[3] = {1e-4, 1e-4, 1e-4}, offset[3] = {0, 0, 0};
  std::vector<LasPoint> pts;
  pipeline::PointData rounded;
  for (const auto& p : scene.cloud->points) {
    LasPoint q{};
    q.x = static_cast<std::int32_t>(std::lround(p.x / 1e-4));
    q.y = static_cast<std::int32_t>(std::lround(p.y / 1e-4));
    q.z = static_cast<std::int32_t>(std::lround(p.z / 1e-4));
    q.return_number = q.returns = 1;
    q.intensity = static_cast<std::uint16_t>(pts.size() % 65536);
    q.gps = 0.5 * static_cast<double>(pts.size());
    pts.push_back(q);
    pcl::PointNormal r;
    r.x = static_cast<float>(1e-4 * q.x);
    r.y = static_cast<float>(1e-4 * q.y);
    r.z = static_cast<float>(1e-4 * q.z);
    rounded.cloud->push_back(r);
  }
  const std::string las = writeFile("scene.las", lasFile(4, 7, pts, scale, offset));
  const std::string ply = scratchDir("las_scene") + "_scene.ply";
  pipeline::writeCloudPly(pipeline::readCloud(las, pipeline::NanPolicy::error), ply, true);
  const std::string floats = scratchDir("las_scene") + "_floats.ply";
  pipeline::writeCloudPly(rounded, floats, true);
  const auto run = [](const std::string& input, const std::string& name, const std::string& more) {
    const std::string out = scratchDir("las_scene_" + name);
    const CliResult r = runSlipfit("run configs/demo.yaml --quiet --set input.path=" + input +
                                   " --set 'segments.render=\"\"' --set output.dir=" + out + more);
    EXPECT_EQ(r.code, 0) << r.err;
    return out;
  };
  const std::string tiled = " --set tiling.size=2 --set tiling.buffer=0.5";
  const std::string a = run(las, "las", ""), b = run(ply, "ply", ""),
                    c = run(las, "las_tiled", tiled), d = run(ply, "ply_tiled", tiled),
                    e = run(floats, "floats", "");
  const auto labels = [](const std::string& dir) {
    return pipeline::readCloud(dir + "/segments.ply", pipeline::NanPolicy::error)
        .numericField("label");
  };
  ASSERT_EQ(labels(a).size(), scene.size());
  EXPECT_EQ(slurp(a + "/segments.ply"), slurp(b + "/segments.ply"));
  EXPECT_EQ(slurp(a + "/primitives.yaml"), slurp(b + "/primitives.yaml"));
  EXPECT_EQ(slurp(c + "/segments.ply"), slurp(d + "/segments.ply"));
  EXPECT_EQ(slurp(c + "/primitives.yaml"), slurp(d + "/primitives.yaml"));
  EXPECT_EQ(labels(a), labels(e));
  // The LAS fields come through the tiles: the tiled output carries every point's gps_time.
  std::vector<double> gps =
      pipeline::readCloud(c + "/segments.ply", pipeline::NanPolicy::error).numericField("gps_time");
  std::sort(gps.begin(), gps.end());
  ASSERT_EQ(gps.size(), pts.size());
  for (std::size_t i = 0; i < gps.size(); ++i)
    ASSERT_EQ(gps[i], pts[i].gps) << i;
}

/// \a data with stage fields label and primitive (point i: label i − 1, primitive 2 i).
void addLabels(pipeline::PointData& data) {
  std::vector<std::int32_t> label, primitive;
  for (std::size_t i = 0; i < data.size(); ++i) {
    label.push_back(static_cast<std::int32_t>(i) - 1);
    primitive.push_back(2 * static_cast<std::int32_t>(i));
  }
  data.setField({"label", label});
  data.setField({"primitive", primitive});
}

// The writer without the pipeline (the sanitizer job's test of it): a LAS 1.2 file of format 1
// with UTM offsets and a LAS 1.4 file of format 7 are read, given labels and written; every field
// reads back equal, label and primitive come back as extra bytes, the file is LAS 1.4 of the
// input's format and grid.
TEST(LasWriter, EveryFieldOfFormats1And7ReadsBackWithTheLabels) {
  for (const int format : {1, 7}) {
    const double scale[3] = {0.001, 0.01, 0.0001};
    const double offset[3] = {500000.0, 5400000.0, -3.0};
    const std::string in =
        writeFile("w" + std::to_string(format) + ".las",
                  lasFile(format == 1 ? 2 : 4, format, threePoints(), scale, offset));
    pipeline::PointData a = pipeline::readCloud(in, pipeline::NanPolicy::error);
    addLabels(a);
    const std::string out = scratchDir("las_writer") + "_" + std::to_string(format) + ".las";
    pipeline::las::writeLas(a, out, {"label", "primitive"});
    const std::string bytes = slurp(out);
    ASSERT_GT(bytes.size(), 375u);
    EXPECT_EQ(bytes[25], 4);
    EXPECT_EQ(bytes[104], static_cast<char>(format));
    const pipeline::PointData b = pipeline::readCloud(out, pipeline::NanPolicy::error);
    ASSERT_EQ(b.size(), 3u);
    EXPECT_EQ(b.frame.grid_scale, a.frame.grid_scale);
    EXPECT_EQ(b.frame.grid_offset, a.frame.grid_offset);
    for (std::size_t i = 0; i < 3; ++i)
      EXPECT_EQ(b.cloud->points[i].getVector3fMap(), a.cloud->points[i].getVector3fMap()) << i;
    for (const auto& f : a.extra.fields)
      EXPECT_EQ(b.numericField(f.name), a.numericField(f.name)) << f.name;
    EXPECT_EQ(b.numericField("label"), (std::vector<double>{-1, 0, 1}));
    EXPECT_EQ(b.numericField("primitive"), (std::vector<double>{0, 2, 4}));
    // The label's descriptor (the first: after the 375-byte header and the VLR's 54) given a
    // scale of 0.5 and an offset of 10: read as raw × 0.5 + 10, in double.
    std::vector<std::uint8_t> scaled(bytes.begin(), bytes.end());
    const std::size_t descriptor = 375 + 54;
    ASSERT_EQ(std::string(reinterpret_cast<const char*>(&scaled[descriptor + 4])), "label");
    scaled[descriptor + 3] |= 8 | 16;
    put<double>(scaled, descriptor + 112, 0.5);
    put<double>(scaled, descriptor + 136, 10.0);
    const pipeline::PointData c = pipeline::readCloud(
        writeFile("scaled" + std::to_string(format) + ".las", scaled), pipeline::NanPolicy::error);
    EXPECT_EQ(c.numericField("label"), (std::vector<double>{9.5, 10, 10.5}));
  }
}

// Points that were not LAS: record format 6, a grid of 1 µm from the floor of the smallest
// coordinate (every coordinate within half a micrometre of where it was), and a point beyond a LAS
// input's 32-bit grid refused in one line naming it.
TEST(LasWriter, OtherPointsGetAFineGridAndPointsOffTheGridAreRefused) {
  Eigen::Matrix3Xd xyz(3, 3);
  xyz << 1.5, -2.25, 0.1234567, 3.0, 0.0, -0.5, 7.0, 1.0, 2.0;
  pipeline::PointData a = pipeline::sampledPointData(xyz, Eigen::Matrix3Xd(), false);
  addLabels(a);
  const std::string out = scratchDir("las_writer") + "_ply.las";
  pipeline::las::writeLas(a, out, {"label", "primitive"});
  const std::string bytes = slurp(out);
  EXPECT_EQ(bytes[104], 6);
  const pipeline::PointData b = pipeline::readCloud(out, pipeline::NanPolicy::error);
  ASSERT_EQ(b.size(), 3u);
  EXPECT_EQ(b.frame.grid_scale, Eigen::Vector3d::Constant(1e-6));
  EXPECT_EQ(b.frame.grid_offset, Eigen::Vector3d(-3.0, -1.0, 1.0));
  // Half the grid step, plus half a float step below 8 (2^-21) as the read-back cloud holds it.
  for (std::size_t i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(b.cloud->points[i].data[k] + b.frame.shift[k],
                  static_cast<double>(a.cloud->points[i].data[k]), 0.5e-6 + std::ldexp(1.0, -22));
  EXPECT_EQ(b.numericField("return_number"), (std::vector<double>{1, 1, 1}));
  EXPECT_EQ(b.numericField("label"), (std::vector<double>{-1, 0, 1}));

  a.frame.grid_scale = Eigen::Vector3d::Constant(1e-3);  // as if read from LAS at 1 mm
  a.cloud->points[2].x = 3.0e6f;                         // 3e9 steps: past int32
  try {
    pipeline::las::writeLas(a, out, {"label"});
    ADD_FAILURE() << "written";
  } catch (const pipeline::RunError& e) {
    EXPECT_THAT(e.what(),
                HasSubstr("point 2: x = 3000000 lies outside the LAS grid of scale 0.001"));
  }
}

/// The shipped scene's points on a LAS grid of 0.1 mm about \a offset, with varied record fields.
std::vector<LasPoint> scenePoints(int format) {
  const pipeline::PointData scene = pipeline::readCloud(
      std::string(kSourceDir) + "/sample_clouds/scene.ply", pipeline::NanPolicy::error);
  std::vector<LasPoint> pts;
  for (std::size_t i = 0; i < scene.size(); ++i) {
    const auto& p = scene.cloud->points[i];
    LasPoint q{};
    q.x = static_cast<std::int32_t>(std::lround(p.x / 1e-4));
    q.y = static_cast<std::int32_t>(std::lround(p.y / 1e-4));
    q.z = static_cast<std::int32_t>(std::lround(p.z / 1e-4));
    const int most = format == 1 ? 7 : 15;
    q.returns = 1 + static_cast<int>(i % static_cast<std::size_t>(most));
    q.return_number = 1 + static_cast<int>(i % static_cast<std::size_t>(q.returns));
    q.intensity = static_cast<std::uint16_t>(i * 7 % 65536);
    q.classification = static_cast<int>(i % (format == 1 ? 32 : 256));
    q.flags = static_cast<int>(i % (format == 1 ? 8 : 16));
    q.channel = static_cast<int>(i % 4);
    q.direction = static_cast<int>(i % 2);
    q.edge = static_cast<int>(i / 2 % 2);
    q.scan_angle =
        format == 1 ? static_cast<int>(i % 181) - 90 : static_cast<int>(i % 30001) - 15000;
    q.user_data = static_cast<int>(i % 256);
    q.source = static_cast<std::uint16_t>(i % 65536);
    q.gps = 3.0e8 + 0.25 * static_cast<double>(i);
    pts.push_back(q);
  }
  return pts;
}

// Issue 38's round trip: a LAS 1.4 file of record format 6 or 7 and a LAS 1.2 file of format 1
// (UTM coordinates) run through the demo pipeline with segments.las, untiled and cut into tiles:
// the output is LAS 1.4 of the input's record format and grid, and every field of every point,
// in the input's order, reads back equal (coordinates to the bit: the same integers on the same
// grid), with label and primitive as extra bytes equal to segments.ply's.
TEST(LasReader, SegmentsLasKeepsEveryInputFieldAndAddsTheLabels) {
  struct Case {
    int minor, format;
    double offset[3];
    bool tiled;
  };
  for (const Case& c :
       {Case{4, 6, {0, 0, 0}, false}, Case{2, 1, {500000.0, 5400000.0, 100.0}, false},
        Case{4, 7, {0, 0, 0}, true}, Case{2, 1, {500000.0, 5400000.0, 100.0}, true}}) {
    const double scale[3] = {1e-4, 1e-4, 1e-4};
    const std::string name =
        std::string(c.tiled ? "tiled" : "roundtrip") + std::to_string(c.format);
    const std::string input = writeFile(
        name + ".las", lasFile(c.minor, c.format, scenePoints(c.format), scale, c.offset));
    const std::string out = scratchDir("las_" + name);
    // A tiled run writes no local copy (its files are not joined across tiles).
    const CliResult r = runSlipfit("run configs/demo.yaml --quiet --set input.path=" + input +
                                   " --set 'segments.render=\"\"' --set segments.las=segments.las" +
                                   (c.tiled ? " --set tiling.size=2 --set tiling.buffer=0.5"
                                            : " --set segments.local_copy=local.ply") +
                                   " --set output.dir=" + out);
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string las = slurp(out + "/segments.las");
    ASSERT_GT(las.size(), 375u);
    EXPECT_EQ(las[25], 4) << "LAS 1.4";
    EXPECT_EQ(static_cast<int>(las[104]), c.format);
    const pipeline::PointData a = pipeline::readCloud(input, pipeline::NanPolicy::error);
    const pipeline::PointData b =
        pipeline::readCloud(out + "/segments.las", pipeline::NanPolicy::error);
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(b.frame.grid_scale, a.frame.grid_scale);
    EXPECT_EQ(b.frame.grid_offset, a.frame.grid_offset);
    ASSERT_EQ(a.frame.shift, b.frame.shift);
    for (std::size_t i = 0; i < a.size(); ++i)
      ASSERT_EQ(a.cloud->points[i].getVector3fMap(), b.cloud->points[i].getVector3fMap()) << i;
    std::size_t fields = 0;
    for (const auto& f : a.extra.fields) {
      EXPECT_EQ(a.numericField(f.name), b.numericField(f.name)) << f.name;
      ++fields;
    }
    EXPECT_EQ(fields, c.format == 1 ? 11u : c.format == 6 ? 12u : 15u);  // readLas's fields
    const pipeline::PointData ply =
        pipeline::readCloud(out + "/segments.ply", pipeline::NanPolicy::error);
    EXPECT_EQ(b.numericField("label"), ply.numericField("label"));
    EXPECT_EQ(b.numericField("primitive"), ply.numericField("primitive"));
    if (c.tiled)
      continue;
    // The float copy in the local frame: the same rows, coordinates less the global shift that
    // primitives.yaml gives, as float (to half a float step at the local magnitude, < 4 m here).
    const YAML::Node report = YAML::LoadFile(out + "/primitives.yaml");
    Eigen::Vector3d shift = Eigen::Vector3d::Zero();
    if (report["global_shift"])
      for (int k = 0; k < 3; ++k)
        shift[k] = report["global_shift"][k].as<double>();
    EXPECT_EQ(shift.isZero(), c.offset[0] == 0.0);
    EXPECT_THAT(slurp(out + "/local.ply"), HasSubstr("property float x\n"));
    const pipeline::PointData local =
        pipeline::readCloud(out + "/local.ply", pipeline::NanPolicy::error);
    ASSERT_EQ(local.size(), a.size());
    EXPECT_EQ(local.numericField("label"), ply.numericField("label"));
    for (std::size_t i = 0; i < a.size(); ++i)
      for (int k = 0; k < 3; ++k)
        ASSERT_NEAR(local.cloud->points[i].data[k] + shift[k],
                    ply.cloud->points[i].data[k] + ply.frame.shift[k], std::ldexp(1.0, -22))
            << i;
    const std::vector<double> labels = b.numericField("label");
    EXPECT_GE(*std::max_element(labels.begin(), labels.end()), 4.0);  // ground, box, ball, ...
  }
}

// A tiled run writes segments.las from its merged segments.ply (tiling/segments_las.h): the rows
// of a cloud written as segmentation writes segments.ply (the input's colours as input_red and
// the like, the segment colours, normals, label and primitive) give the very bytes the untiled
// writer gives for the cloud itself: on a LAS input's grid and record format (format 7, colours),
// and on the power-of-ten grid of another input (georeferenced coordinates, a pass for the bounds).
TEST(LasWriter, AMergedSegmentsPlyGivesTheBytesOfTheCloudsOwnLas) {
  for (const bool las_input : {true, false}) {
    const double scale[3] = {1e-3, 1e-3, 1e-3}, offset[3] = {500000.0, 5400000.0, 100.0};
    std::vector<LasPoint> pts = threePoints();
    for (int k = 0; k < 200; ++k)  // more than one row of each kind, spread over metres
      pts.push_back({k * 37,
                     -k * 53,
                     k * 11,
                     static_cast<std::uint16_t>(k),
                     1,
                     1,
                     k % 32,
                     k % 4,
                     k % 4,
                     k % 2,
                     0,
                     k % 90,
                     k % 256,
                     static_cast<std::uint16_t>(k),
                     0.5 * k,
                     {static_cast<std::uint16_t>(257 * k), 1, 2}});
    const std::string input = writeFile(las_input ? "merged7.las" : "merged7_other.las",
                                        lasFile(4, 7, pts, scale, offset));
    pipeline::PointData data = pipeline::readCloud(input, pipeline::NanPolicy::error);
    if (!las_input) {  // as if the input had been another format: the writer picks the grid
      data.frame.las_format = -1;
      data.frame.grid_scale.setZero();
      data.frame.grid_offset.setZero();
    }
    addLabels(data);
    std::vector<std::uint8_t> red, green, blue;
    for (std::size_t i = 0; i < data.size(); ++i) {
      red.push_back(static_cast<std::uint8_t>(i));
      green.push_back(static_cast<std::uint8_t>(3 * i));
      blue.push_back(7);
    }
    data.setField({"red", red});
    data.setField({"green", green});
    data.setField({"blue", blue});
    data.has_normals = true;
    const std::string dir = scratchDir(las_input ? "merged_las" : "merged_other");
    pipeline::writeCloudPly(data, dir + "_segments.ply", true);
    ASSERT_THAT(slurp(dir + "_segments.ply"), HasSubstr("property ushort input_red\n"));
    pipeline::las::writeLas(data, dir + "_own.las", {"label", "primitive"});
    pipeline::tiling::writeSegmentsLas(
        dir + "_segments.ply", las_input ? input : dir + "_segments.ply", dir + "_merged.las");
    const std::string own = slurp(dir + "_own.las");
    ASSERT_GT(own.size(), 375u + 203u * 36u);
    EXPECT_TRUE(own == slurp(dir + "_merged.las")) << (las_input ? "LAS input" : "other input");
    const pipeline::PointData back =
        pipeline::readCloud(dir + "_merged.las", pipeline::NanPolicy::error);
    // The record's colour is the input's (the segment colours are not written to LAS).
    EXPECT_EQ(back.numericField("red"),
              pipeline::readCloud(input, pipeline::NanPolicy::error).numericField("red"));
    EXPECT_EQ(back.numericField("label"), data.numericField("label"));
  }
}

}  // namespace
}  // namespace slipfit::testing
