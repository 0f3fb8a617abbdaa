#include "slipfit/pipeline/cloud_io.h"
#include "slipfit/pipeline/errors.h"

#include "run_cli.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include <pcl/conversions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

namespace slipfit::pipeline {
namespace {

using ::testing::HasSubstr;
using Field = pcl::PCLPointField;

/// A cloud with normals, curvature, typed extra fields and stage fields, with awkward values.
PointData richCloud() {
  PointData d;
  const std::size_t n = 257;
  d.cloud->resize(n);
  d.has_normals = d.has_curvature = true;
  pcl::PCLPointCloud2& e = d.extra;
  e.width = static_cast<std::uint32_t>(n);
  e.height = 1;
  const std::pair<const char*, std::uint8_t> fields[] = {
      {"class_id", Field::UINT8},    {"offset", Field::INT8},     {"ring", Field::UINT16},
      {"delta", Field::INT16},       {"stamp", Field::UINT32},    {"count", Field::INT32},
      {"intensity", Field::FLOAT32}, {"gps_time", Field::FLOAT64}};
  const std::uint32_t sizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
  for (std::size_t f = 0; f < 8; ++f) {
    Field pf;
    pf.name = fields[f].first;
    pf.datatype = fields[f].second;
    pf.count = 1;
    pf.offset = e.point_step;
    e.fields.push_back(pf);
    e.point_step += sizes[f];
  }
  e.row_step = e.point_step * e.width;
  e.data.resize(e.row_step);
  std::vector<std::int32_t> label(n);
  std::vector<float> weight(n);
  for (std::size_t i = 0; i < n; ++i) {
    auto& p = (*d.cloud)[i];
    const float t = static_cast<float>(i);
    p.x = 1e4f + t * 1.0000001f;
    p.y = -t * 3.3333333e-7f;
    p.z = std::nextafter(0.1f * t, 1e9f);
    p.getNormalVector3fMap() = Eigen::Vector3f(std::sin(t), std::cos(t), 0.3f).normalized();
    p.curvature = 1.0f / (1.0f + t);
    for (std::size_t b = 0; b < e.point_step; ++b)
      e.data[i * e.point_step + b] = static_cast<std::uint8_t>((i * 131 + b * 17) & 0xff);
    // Keep the float fields finite (the byte pattern could be NaN, which does not compare).
    const float intensity = t * 0.7f;
    const double gps = 1.6e9 + t * 1e-6;
    std::memcpy(&e.data[i * e.point_step + e.fields[6].offset], &intensity, 4);
    std::memcpy(&e.data[i * e.point_step + e.fields[7].offset], &gps, 8);
    label[i] = static_cast<std::int32_t>(i % 7) - 1;
    weight[i] = 1.0f / 3.0f * t;
  }
  d.setField({"label", label});
  d.setField({"weight", weight});
  return d;
}

/// The bytes of field \a name in every row of \a blob.
std::vector<std::uint8_t> column(const pcl::PCLPointCloud2& blob, const std::string& name) {
  for (const auto& f : blob.fields)
    if (f.name == name) {
      const std::size_t size = pcl::getFieldSize(f.datatype);
      std::vector<std::uint8_t> out;
      for (std::size_t i = 0; i < blob.width * blob.height; ++i)
        out.insert(out.end(), blob.data.begin() + i * blob.point_step + f.offset,
                   blob.data.begin() + i * blob.point_step + f.offset + size);
      return out;
    }
  ADD_FAILURE() << "no field " << name;
  return {};
}

void expectSameBits(const PointData& a, const PointData& b) {
  const pcl::PCLPointCloud2 ba = toBlob(a), bb = toBlob(b);
  ASSERT_EQ(ba.width, bb.width);
  ASSERT_EQ(ba.fields.size(), bb.fields.size());
  for (const auto& f : ba.fields) {
    EXPECT_EQ(column(ba, f.name), column(bb, f.name)) << "field " << f.name;
  }
}

TEST(CloudIo, BinaryPlyRoundTripIsBitExact) {
  const PointData d = richCloud();
  const std::string path = testing::scratchFile("io_bin.ply", "");
  writeCloudPly(d, path, true);
  ReadReport report;
  const PointData back = readCloud(path, NanPolicy::error, &report);
  EXPECT_TRUE(back.has_normals);
  EXPECT_TRUE(back.has_curvature);
  EXPECT_EQ(report.extra_fields,
            "class_id, offset, ring, delta, stamp, count, intensity, gps_time, label, weight");
  // Stage fields come back as extra fields; toBlob orders them the same way.
  expectSameBits(d, back);
}

TEST(CloudIo, AsciiPlyRoundTripIsBitExact) {
  const PointData d = richCloud();
  const std::string path = testing::scratchFile("io_ascii.ply", "");
  writeCloudPly(d, path, false);
  EXPECT_THAT(testing::slurp(path), HasSubstr("format ascii 1.0"));
  expectSameBits(d, readCloud(path, NanPolicy::error));
}

TEST(CloudIo, ReadsPcdAndKeepsItsFields) {
  pcl::PointCloud<pcl::PointXYZRGBNormal> c;
  for (int i = 0; i < 10; ++i) {
    pcl::PointXYZRGBNormal p;
    p.x = static_cast<float>(i);
    p.y = p.z = 0.5f;
    p.normal_x = 1;
    p.normal_y = p.normal_z = 0;
    p.r = static_cast<std::uint8_t>(10 * i);
    p.g = 1;
    p.b = 2;
    p.curvature = 0.25f;
    c.push_back(p);
  }
  const std::string path = testing::scratchFile("io.pcd", "");
  ASSERT_EQ(pcl::io::savePCDFileBinaryCompressed(path, c), 0);
  ReadReport report;
  const PointData d = readCloud(path, NanPolicy::error, &report);
  ASSERT_EQ(d.size(), 10u);
  EXPECT_TRUE(d.has_normals);
  EXPECT_EQ((*d.cloud)[3].x, 3.0f);
  EXPECT_EQ((*d.cloud)[3].normal_x, 1.0f);
  EXPECT_EQ(report.extra_fields, "rgb");
  std::uint32_t rgb;
  std::memcpy(&rgb, d.extra.data.data() + 3 * d.extra.point_step, 4);
  EXPECT_EQ((rgb >> 16) & 0xff, 30u);
}

// The header checks (pipeline/src/header_guard.cpp) must accept what PCL's own writers produce:
// organized clouds (obj_info grid + range_grid), camera elements, colours with alpha, faces.
TEST(CloudIo, AcceptsEveryLayoutPclWrites) {
  pcl::PointCloud<pcl::PointXYZRGBA> organized(4, 3);
  for (std::size_t i = 0; i < organized.size(); ++i) {
    auto& p = organized[i];
    p.x = static_cast<float>(i % 4);
    p.y = static_cast<float>(i / 4);
    p.z = i == 5 ? std::numeric_limits<float>::quiet_NaN() : 1.0f;  // a missing depth
    p.r = static_cast<std::uint8_t>(i);
    p.g = 2;
    p.b = 3;
    p.a = 255;
  }
  organized.is_dense = false;
  pcl::PCLPointCloud2 blob;
  pcl::toPCLPointCloud2(organized, blob);
  for (const bool binary : {true, false})
    for (const bool camera : {false, true}) {
      SCOPED_TRACE(std::string(binary ? "binary" : "ascii") + (camera ? " camera" : " range_grid"));
      const std::string path = testing::scratchFile("organized.ply", "");
      pcl::PLYWriter writer;
      ASSERT_EQ(writer.write(path, blob, Eigen::Vector4f::Zero(), Eigen::Quaternionf::Identity(),
                             binary, camera),
                0);
      ReadReport report;
      const PointData d = readCloud(path, NanPolicy::skip, &report);
      EXPECT_EQ(report.points_read, 12u);  // the grid, with the missing cell as NaN
      EXPECT_EQ(d.size(), 11u);
      EXPECT_EQ((*d.cloud)[10].x, 3.0f);
      EXPECT_EQ((*d.cloud)[10].y, 2.0f);
    }
  // The PCD encodings, from a PCLPointCloud2: PCL 1.13 leaves up to a page of zeros after the
  // binary data, which is no data past the announced points.
  for (const int encoding : {0, 1, 2}) {
    SCOPED_TRACE("PCD encoding " + std::to_string(encoding));
    const std::string path = testing::scratchFile("organized.pcd", "");
    pcl::PCDWriter writer;
    const int status = encoding == 0   ? writer.writeBinary(path, blob)
                       : encoding == 1 ? writer.writeASCII(path, blob)
                                       : writer.writeBinaryCompressed(path, blob);
    ASSERT_EQ(status, 0);
    const PointData d = readCloud(path, NanPolicy::skip);
    EXPECT_EQ(d.size(), 11u);
    EXPECT_EQ((*d.cloud)[10].x, 3.0f);
    ASSERT_TRUE(d.sensor.has_value());
    EXPECT_EQ(d.sensor->width, 4u);
    EXPECT_EQ(d.sensor->height, 3u);
    ASSERT_EQ(d.pixels.size(), 11u);
    EXPECT_EQ(d.pixels[10], 11);
  }

  // Hand-written: CRLF line ends, comments, obj_info, colours with alpha, a face element.
  const std::string hand = testing::scratchFile(
      "hand.ply",
      "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\nobj_info scanner X\r\n"
      "element vertex 3\r\nproperty float x\r\nproperty float y\r\nproperty float z\r\n"
      "property uchar red\r\nproperty uchar green\r\nproperty uchar blue\r\n"
      "property uchar alpha\r\nelement face 1\r\nproperty list uchar int vertex_indices\r\n"
      "end_header\r\n0 0 0 1 2 3 4\r\n1 0 0 5 6 7 8\r\n0 1 0 9 10 11 12\r\n3 0 1 2\r\n");
  ReadReport report;
  const PointData d = readCloud(hand, NanPolicy::error, &report);
  EXPECT_EQ(d.size(), 3u);
  EXPECT_EQ(report.extra_fields, "rgba");
}

// PCL packs PLY colours into one rgb(a) field when reading; they are written back as the uchar
// red, green, blue (alpha) that viewers show, in both encodings.
TEST(CloudIo, ColoursComeBackAsUcharProperties) {
  const std::string in = testing::scratchFile(
      "colours.ply",
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty "
      "float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar "
      "alpha\nend_header\n0 0 0 200 100 50 25\n1 2 3 1 2 3 4\n");
  const PointData d = readCloud(in, NanPolicy::error);
  for (const bool binary : {true, false}) {
    SCOPED_TRACE(binary ? "binary" : "ascii");
    const std::string out = testing::scratchFile("colours_out.ply", "");
    writeCloudPly(d, out, binary);
    std::ifstream f(out, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    EXPECT_THAT(text, HasSubstr("property uchar red\nproperty uchar green\nproperty uchar "
                                "blue\nproperty uchar alpha\n"));
    if (!binary)
      EXPECT_THAT(text, HasSubstr("end_header\n0 0 0 200 100 50 25\n1 2 3 1 2 3 4\n"));
    const PointData back = readCloud(out, NanPolicy::error);
    ASSERT_EQ(back.extra.fields.size(), 1u);
    EXPECT_EQ(back.extra.fields[0].name, "rgba");
    EXPECT_EQ(back.extra.data, d.extra.data);
  }
}

std::string readError(const std::string& path, NanPolicy policy = NanPolicy::error) {
  try {
    readCloud(path, policy);
  } catch (const RunError& e) {
    return e.what();
  }
  return "no error";
}

const char* kAsciiHeader =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float "
    "z\nend_header\n";

TEST(CloudIo, NanPointsAreAnErrorOrSkippedWithACount) {
  const std::string path =
      testing::scratchFile("nan.ply", std::string(kAsciiHeader) + "0 0 0\nnan 1 1\n2 2 2\n");
  EXPECT_THAT(
      readError(path),
      HasSubstr(
          "point 1 has a non-finite coordinate (NaN, inf or not a number); set input.nan: skip"));
  ReadReport r;
  const PointData d = readCloud(path, NanPolicy::skip, &r);
  EXPECT_EQ(d.size(), 2u);
  EXPECT_EQ(r.dropped, 1u);
  EXPECT_EQ((*d.cloud)[1].x, 2.0f);
  const std::string all =
      testing::scratchFile("allnan.ply", std::string(kAsciiHeader) + "nan 0 0\n0 nan 0\n0 0 inf\n");
  EXPECT_THAT(readError(all, NanPolicy::skip), HasSubstr("none of its 3 points has finite values"));
  // A finite double beyond float's range is named as such, not as NaN (issue 15).
  const std::string big = testing::scratchFile(
      "big.ply",
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\nproperty "
      "double z\nend_header\n0 0 0\n1e39 0 0\n");
  EXPECT_THAT(readError(big),
              HasSubstr("point 1 has a coordinate beyond float's range (1e+39 > 3.4e38)"));
}

// A point whose given normal is NaN or zero keeps its place (whatever the policy: coordinates
// decide it), its normal and curvature NaN, and the report counts it and names the first.
TEST(CloudIo, PointsWithMissingNormalsAreKeptAndCounted) {
  const std::string path = testing::scratchFile(
      "nan_normals.ply",
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty "
      "float z\nproperty float nx\nproperty float ny\nproperty float nz\nend_header\n0 0 0 0 0 "
      "1\n1 0 0 nan 0 1\n2 0 0 0 0 0\n3 0 0 0 0 1\n");
  for (const NanPolicy policy : {NanPolicy::error, NanPolicy::skip}) {
    ReadReport r;
    const PointData d = readCloud(path, policy, &r);
    ASSERT_EQ(d.size(), 4u);
    EXPECT_TRUE(d.has_normals);
    EXPECT_EQ(r.normals_missing, 2u);
    EXPECT_EQ(r.first_missing_normal, 1u);
    EXPECT_TRUE(std::isnan((*d.cloud)[1].normal_x));
    EXPECT_TRUE(std::isnan((*d.cloud)[2].normal_z));
    EXPECT_EQ((*d.cloud)[3].normal_z, 1.0f);
  }
}

// An organized PCD (4 × 2, one NaN point) with a VIEWPOINT: the NaN point is dropped by default
// and the sensor's pose and the grid are kept for the picture and the report; a PLY has none.
TEST(CloudIo, OrganizedPcdKeepsItsSensorPose) {
  const std::string path = testing::scratchFile(
      "organized.pcd",
      "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH "
      "4\nHEIGHT 2\nVIEWPOINT 1 2 3 0.7071068 0.7071068 0 0\nPOINTS 8\nDATA ascii\n0 0 1\n1 "
      "0 1\n2 0 1\nnan nan nan\n0 1 1\n1 1 1\n2 1 1\n3 1 1\n");
  ReadReport r;
  const PointData d = readCloud(path, NanPolicy::skip, &r);
  EXPECT_EQ(d.size(), 7u);
  ASSERT_TRUE(d.sensor.has_value());
  EXPECT_EQ(d.sensor->width, 4u);
  EXPECT_EQ(d.sensor->height, 2u);
  // Each kept point keeps its pixel: the NaN at pixel 3 is skipped.
  EXPECT_EQ(d.pixels, (std::vector<std::int32_t>{0, 1, 2, 4, 5, 6, 7}));
  EXPECT_LT((d.sensor->origin - Eigen::Vector3d(1, 2, 3)).norm(), 1e-6);
  EXPECT_NEAR(d.sensor->orientation.angularDistance(
                  Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()))),
              0.0, 1e-6);
  const std::string ply =
      testing::scratchFile("plain.ply", std::string(kAsciiHeader) + "0 0 0\n1 1 1\n2 2 2\n");
  EXPECT_FALSE(readCloud(ply, NanPolicy::error).sensor.has_value());
  EXPECT_TRUE(readCloud(ply, NanPolicy::error).pixels.empty());
}

// A sensor's organized view as PCD, binary and ascii: read back, both are the same view (the
// rows, their pixels, the grid and the pose) with the same bits in every field.
TEST(CloudIo, AnOrganizedViewIsThePcdsInBothEncodings) {
  PointData d = richCloud();
  SensorPose pose;
  pose.origin = Eigen::Vector3d(0.25, -1.5, 2.0);
  pose.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()));
  pose.width = 16;
  pose.height = 20;
  d.sensor = pose;
  for (std::size_t i = 0; i < d.size(); ++i)
    d.pixels.push_back(static_cast<std::int32_t>(i + i / 5));  // 307 at most, of 320 cells
  const std::string binary = testing::scratchFile("view_binary.pcd", "");
  const std::string ascii = testing::scratchFile("view_ascii.pcd", "");
  writeCloudPcd(d, binary, true);
  writeCloudPcd(d, ascii, false);
  const PointData b = readCloud(binary, NanPolicy::skip), a = readCloud(ascii, NanPolicy::skip);
  for (const PointData* r : {&b, &a}) {
    ASSERT_EQ(r->size(), d.size());
    ASSERT_TRUE(r->sensor.has_value());
    EXPECT_EQ(r->sensor->width, 16u);
    EXPECT_EQ(r->sensor->height, 20u);
    EXPECT_TRUE(r->sensor->origin.isApprox(pose.origin, 1e-6));
    EXPECT_LT(r->sensor->orientation.angularDistance(pose.orientation), 1e-6);
    EXPECT_EQ(r->pixels, d.pixels);
    for (std::size_t i = 0; i < d.size(); ++i)
      ASSERT_EQ((*r->cloud)[i].getVector3fMap(), (*d.cloud)[i].getVector3fMap()) << "row " << i;
  }
  expectSameBits(b, a);
}

TEST(CloudIo, BadFilesGiveOneClearError) {
  EXPECT_THAT(readError("/nonexistent/cloud.ply"),
              HasSubstr("input '/nonexistent/cloud.ply': no such file"));
  EXPECT_THAT(readError(testing::kScratchDir), HasSubstr("is a directory"));
  EXPECT_THAT(readError(testing::scratchFile("empty.ply", "")), HasSubstr("the file is empty"));
  EXPECT_THAT(readError(testing::scratchFile("cloud.xyz", "1 2 3\n")),
              HasSubstr("unsupported file type '.xyz'"));
  EXPECT_THAT(
      readError(testing::scratchFile("zero.ply",
                                     "ply\nformat ascii 1.0\nelement vertex 0\nproperty float "
                                     "x\nproperty float y\nproperty float z\nend_header\n")),
      HasSubstr("the cloud is empty (0 points)"));
  EXPECT_THAT(readError(testing::scratchFile(
                  "word.ply", std::string(kAsciiHeader) + "0 0 0\n1 one 1\n2 2 2\n")),
              HasSubstr("point 1 has a non-finite coordinate (NaN, inf or not a number)"));
  EXPECT_THAT(
      readError(testing::scratchFile("short.ply", std::string(kAsciiHeader) + "0 0 0\n1 1 1\n")),
      HasSubstr("truncated: the header announces 3 vertices and at least 18 bytes of data, but "
                "only 12 bytes follow it"));
  EXPECT_THAT(readError(testing::scratchFile(
                  "noxyz.ply",
                  "ply\nformat ascii 1.0\nelement vertex 1\nproperty float a\nend_header\n1\n")),
              HasSubstr("no x, y, z fields"));

  // A binary PLY cut short.
  const PointData d = richCloud();
  const std::string full = testing::scratchFile("trunc_src.ply", "");
  writeCloudPly(d, full, true);
  std::string bytes = testing::slurp(full);
  bytes.resize(bytes.size() - 100);
  EXPECT_THAT(readError(testing::scratchFile("truncated.ply", bytes)), HasSubstr("input '"));
  EXPECT_THAT(readError(testing::scratchFile("truncated.ply", bytes)),
              ::testing::AnyOf(HasSubstr("truncated"), HasSubstr("not a readable PLY")));
}

/// The values of \a name in \a extra, as float (every carried field here is float).
std::vector<float> carried(const pcl::PCLPointCloud2& extra, const std::string& name) {
  std::vector<float> values;
  for (const auto& f : extra.fields)
    if (f.name == name)
      for (std::size_t i = 0; i < extra.width; ++i) {
        float v = 0.0f;
        std::memcpy(&v, extra.data.data() + i * extra.point_step + f.offset, 4);
        values.push_back(v);
      }
  return values;
}

// Issue 40: a PCD field of COUNT 3 and a lone nx (no ny, nz: not a normal) vanished from the
// outputs without a word. They are carried now, by a stated rule: COUNT k as name_0 … name_{k−1};
// normal components that make no normal, and a curvature without normals, as input_<name>.
TEST(CloudIo, FieldsOfSeveralValuesAndLoneNormalComponentsAreCarried) {
  const std::string pcd = testing::scratchFile("count3.pcd", [] {
    std::string text =
        "VERSION 0.7\nFIELDS x y z hist\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 3\nWIDTH 30\n"
        "HEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 30\nDATA ascii\n";
    for (int i = 0; i < 30; ++i)
      text += std::to_string(i % 5) + " " + std::to_string(i / 5) + " 0 " + std::to_string(i) +
              " " + std::to_string(2 * i) + " " + std::to_string(3 * i) + "\n";
    return text;
  }());
  ReadReport report;
  PointData data = readCloud(pcd, NanPolicy::error, &report);
  EXPECT_EQ(report.extra_fields, "hist_0, hist_1, hist_2");
  for (int k = 0; k < 3; ++k) {
    const std::vector<float> v = carried(data.extra, "hist_" + std::to_string(k));
    ASSERT_EQ(v.size(), 30u) << k;
    for (int i = 0; i < 30; ++i)
      EXPECT_EQ(v[static_cast<std::size_t>(i)], static_cast<float>((k + 1) * i)) << k << " " << i;
  }
  const std::string ply = testing::scratchFile("lone_nx.ply", [] {
    std::string text =
        "ply\nformat ascii 1.0\nelement vertex 30\nproperty float x\nproperty float y\n"
        "property float z\nproperty float nx\nproperty float curvature\nend_header\n";
    for (int i = 0; i < 30; ++i)
      text += std::to_string(i % 5) + " " + std::to_string(i / 5) + " 0 " + std::to_string(i) +
              " 0.5\n";
    return text;
  }());
  data = readCloud(ply, NanPolicy::error, &report);
  EXPECT_FALSE(data.has_normals);
  EXPECT_EQ(report.extra_fields, "input_normal_x, input_curvature");  // PCL names nx normal_x
  const std::vector<float> nx = carried(data.extra, "input_normal_x");
  ASSERT_EQ(nx.size(), 30u);
  for (int i = 0; i < 30; ++i)
    EXPECT_EQ(nx[static_cast<std::size_t>(i)], static_cast<float>(i));
  EXPECT_EQ(carried(data.extra, "input_curvature"), std::vector<float>(30, 0.5f));
}

}  // namespace
}  // namespace slipfit::pipeline
