// What a PCL application reads from slipfit's segmentation outputs, read with PCL's own readers
// into PCL's point types: segments.ply (colours; its int label is the benchmark scorers' and
// CloudCompare's convention, −1 = no segment) and the PCD in PCL's conventions (label uint32,
// 4294967295 = no segment; packed rgb), for each shipped segmentation config; organized PCDs of
// a sensor's view.
#include "run_cli.h"
#include "slipfit/pipeline/cloud_io.h"
#include "slipfit/render/segment_palette.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace slipfit::testing {
namespace {

using ::testing::HasSubstr;

/// The colour slipfit gives a point of segment \a label (−1: none), packed as PCL packs it.
std::uint32_t segmentRgb(std::int32_t label) {
  const Rgb c = label < 0 ? kUnassignedColour : segmentColour(static_cast<std::size_t>(label));
  return std::uint32_t{c[0]} << 16 | std::uint32_t{c[1]} << 8 | c[2];
}

/// The labels of segments.ply as slipfit reads them (int, −1 = no segment).
std::vector<std::int32_t> labelsOf(const std::string& ply) {
  const std::vector<double> v =
      pipeline::readCloud(ply, pipeline::NanPolicy::error).numericField("label");
  return {v.begin(), v.end()};
}

class ShippedSegmentation : public ::testing::TestWithParam<const char*> {};

TEST_P(ShippedSegmentation, OutputsLoadInPclWithTheirLabelsAndColours) {
  const std::string config = GetParam();
  const std::string out = scratchDir("pcl_interop_" + config);
  const CliResult r =
      runSlipfit("run configs/" + config +
                 ".yaml --quiet --set segments.pcd=segments.pcd --set output.dir=" + out);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<std::int32_t> labels = labelsOf(out + "/segments.ply");
  ASSERT_FALSE(labels.empty());
  std::size_t assigned = 0, unassigned = 0;
  for (const std::int32_t l : labels)
    ++(l >= 0 ? assigned : unassigned);
  // Both kinds present, or the checks below would not see one of them.
  ASSERT_GT(assigned, labels.size() / 2);
  ASSERT_GT(unassigned, 0u) << "no unassigned point to check the mark of";

  // segments.ply into PCL's PointXYZRGBNormal: the segment colours, the normals.
  pcl::PointCloud<pcl::PointXYZRGBNormal> ply;
  ASSERT_EQ(pcl::io::loadPLYFile(out + "/segments.ply", ply), 0);
  ASSERT_EQ(ply.size(), labels.size());
  std::size_t wrong_colour = 0;
  for (std::size_t i = 0; i < ply.size(); ++i)
    wrong_colour += (ply[i].rgba & 0xffffffu) != segmentRgb(labels[i]) ? 1 : 0;
  EXPECT_EQ(wrong_colour, 0u);

  // The PCD into PointXYZRGBL (labels and colours) and PointXYZLNormal (labels and normals).
  pcl::PointCloud<pcl::PointXYZRGBL> rgbl;
  ASSERT_EQ(pcl::io::loadPCDFile(out + "/segments.pcd", rgbl), 0);
  pcl::PointCloud<pcl::PointXYZLNormal> lnormal;
  ASSERT_EQ(pcl::io::loadPCDFile(out + "/segments.pcd", lnormal), 0);
  ASSERT_EQ(rgbl.size(), labels.size());
  ASSERT_EQ(lnormal.size(), labels.size());
  constexpr std::uint32_t kNoSegment = std::numeric_limits<std::uint32_t>::max();
  std::size_t wrong_label = 0, wrong_pcd_colour = 0, moved = 0;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    const std::uint32_t expected =
        labels[i] < 0 ? kNoSegment : static_cast<std::uint32_t>(labels[i]);
    wrong_label += rgbl[i].label != expected || lnormal[i].label != expected ? 1 : 0;
    wrong_pcd_colour += (rgbl[i].rgba & 0xffffffu) != segmentRgb(labels[i]) ? 1 : 0;
    // The same float coordinates and normals as the PLY (both written from the same floats).
    moved += rgbl[i].getVector3fMap() != ply[i].getVector3fMap() ||
                     lnormal[i].getNormalVector3fMap() != ply[i].getNormalVector3fMap()
                 ? 1
                 : 0;
  }
  EXPECT_EQ(wrong_label, 0u);
  EXPECT_EQ(wrong_pcd_colour, 0u);
  EXPECT_EQ(moved, 0u);
}

// segment_scene runs the demo's stages with a voxel subsample in front; its outputs are written by
// the same writers (the demo case runs them under the sanitizers).
INSTANTIATE_TEST_SUITE_P(Configs, ShippedSegmentation, ::testing::Values("demo", "segment_scene"),
                         [](const auto& info) { return std::string(info.param); });

TEST(PclInterop, InputColoursAreKeptUnderInputNamesAndPclShowsTheSegments) {
  // The shipped scene with a colour of its own (PCL writes it as uchar red, green, blue).
  pcl::PointCloud<pcl::PointXYZ> scene;
  ASSERT_EQ(pcl::io::loadPLYFile(std::string(kSourceDir) + "/sample_clouds/scene.ply", scene), 0);
  pcl::PointCloud<pcl::PointXYZRGB> coloured;
  for (const auto& p : scene) {
    pcl::PointXYZRGB q(std::uint8_t{12}, std::uint8_t{34}, std::uint8_t{56});
    q.getVector3fMap() = p.getVector3fMap();
    coloured.push_back(q);
  }
  const std::string out = scratchDir("pcl_interop_colours");
  const std::string input = out + "_input.ply";
  ASSERT_EQ(pcl::io::savePLYFileBinary(input, coloured), 0);
  const CliResult r = runSlipfit("run configs/demo.yaml --quiet --set input.path=" + input +
                                 " --set segments.render='' --set output.dir=" + out);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(slurp(out + "/segments.ply").substr(0, 2000), HasSubstr(" input_rgb\n"));

  const pipeline::PointData segments =
      pipeline::readCloud(out + "/segments.ply", pipeline::NanPolicy::error);
  const std::vector<double> label_values = segments.numericField("label");
  const std::vector<std::int32_t> labels(label_values.begin(), label_values.end());
  pcl::PointCloud<pcl::PointXYZRGBNormal> ply;
  ASSERT_EQ(pcl::io::loadPLYFile(out + "/segments.ply", ply), 0);
  ASSERT_EQ(ply.size(), labels.size());
  std::size_t wrong_colour = 0;
  for (std::size_t i = 0; i < ply.size(); ++i)
    wrong_colour += (ply[i].rgba & 0xffffffu) != segmentRgb(labels[i]) ? 1 : 0;
  EXPECT_EQ(wrong_colour, 0u) << "PCL shows the input's colour, not the segments'";
  // ... and the input's colour is still there, packed under its input_ name.
  const auto& extra = segments.extra;
  const auto field = std::find_if(extra.fields.begin(), extra.fields.end(),
                                  [](const auto& f) { return f.name == "input_rgb"; });
  ASSERT_NE(field, extra.fields.end());
  std::size_t wrong_input = 0;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, extra.data.data() + i * extra.point_step + field->offset, sizeof bits);
    wrong_input += (bits & 0xffffffu) != std::uint32_t{12 << 16 | 34 << 8 | 56} ? 1 : 0;
  }
  EXPECT_EQ(wrong_input, 0u);
}

// A sensor's organized view written as PCD is organized in PCL's way — width × height, NaN where
// the sensor had no return, its pose as VIEWPOINT — and read back it is the same view: the same
// points at the same pixels (the PLY's grid_index), the sensor's pose and grid. The segments PCD
// of that view is a label image of the same grid, each pixel's label the PLY row's.
TEST(PclInterop, AnOrganizedViewIsWrittenAsAnOrganizedPcdAndReadBackAsTheSameView) {
  // A terrestrial LiDAR's angular grid: its pose is not the identity at the origin (a depth
  // camera's frame is in its own coordinates).
  const std::string scan =
      " --set scan.sensor=lidar --set scan.scene=yard --set scan.width=160 "
      "--set scan.height=120 --set seed=4";
  const std::string as_ply = scratchDir("pcl_interop_scan_ply");
  const std::string as_pcd = scratchDir("pcl_interop_scan_pcd");
  const std::string segmented = scratchDir("pcl_interop_scan_segments");
  CliResult r =
      runSlipfit("run configs/sample_scan.yaml --quiet" + scan + " --set output.dir=" + as_ply);
  ASSERT_EQ(r.code, 0) << r.err;
  r = runSlipfit("run configs/sample_scan.yaml --quiet" + scan +
                 " --set output.cloud=cloud.pcd --set output.dir=" + as_pcd);
  ASSERT_EQ(r.code, 0) << r.err;
  const pipeline::PointData rows =
      pipeline::readCloud(as_ply + "/cloud.ply", pipeline::NanPolicy::error);
  const std::vector<double> cell = rows.numericField("grid_index");
  ASSERT_GT(rows.size(), 1000u);

  pcl::PointCloud<pcl::PointXYZ> grid;
  ASSERT_EQ(pcl::io::loadPCDFile(as_pcd + "/cloud.pcd", grid), 0);
  EXPECT_EQ(grid.width, 160u);
  EXPECT_EQ(grid.height, 120u);
  EXPECT_FALSE(grid.is_dense);
  std::size_t finite = 0;
  for (const auto& p : grid)
    finite += std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) ? 1 : 0;
  EXPECT_EQ(finite, rows.size()) << "one finite pixel per return, NaN elsewhere";
  std::size_t moved = 0;
  for (std::size_t j = 0; j < rows.size(); ++j)
    moved += grid[static_cast<std::size_t>(cell[j])].getVector3fMap() !=
                     (*rows.cloud)[j].getVector3fMap()
                 ? 1
                 : 0;
  EXPECT_EQ(moved, 0u) << "returns not at their grid_index pixel";
  EXPECT_GT(grid.sensor_origin_.head<3>().norm(), 1.0f) << "the scanner's pose is not recorded";

  // slipfit reads the PCD back as the sensor's view: its rows, pixels and pose.
  const pipeline::PointData view =
      pipeline::readCloud(as_pcd + "/cloud.pcd", pipeline::NanPolicy::skip);
  ASSERT_EQ(view.size(), rows.size());
  ASSERT_TRUE(view.sensor.has_value());
  EXPECT_EQ(view.sensor->width, 160u);
  EXPECT_EQ(view.sensor->height, 120u);
  EXPECT_TRUE(view.sensor->origin.isApprox(grid.sensor_origin_.head<3>().cast<double>(), 1e-6));
  ASSERT_EQ(view.pixels.size(), rows.size());
  std::size_t wrong_pixel = 0;
  for (std::size_t j = 0; j < rows.size(); ++j)
    wrong_pixel += view.pixels[j] != static_cast<std::int32_t>(cell[j]) ? 1 : 0;
  EXPECT_EQ(wrong_pixel, 0u);

  r = runSlipfit("run configs/demo.yaml --quiet --set input.path=" + as_pcd +
                 "/cloud.pcd --set segments.pcd=segments.pcd --set segments.render='' "
                 "--set output.dir=" +
                 segmented);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<std::int32_t> labels = labelsOf(segmented + "/segments.ply");
  ASSERT_EQ(labels.size(), rows.size());
  pcl::PointCloud<pcl::PointXYZRGBL> image;
  ASSERT_EQ(pcl::io::loadPCDFile(segmented + "/segments.pcd", image), 0);
  ASSERT_EQ(image.width, 160u);
  ASSERT_EQ(image.height, 120u);
  constexpr std::uint32_t kNoSegment = std::numeric_limits<std::uint32_t>::max();
  std::size_t wrong_label = 0;
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const std::uint32_t expected =
        labels[j] < 0 ? kNoSegment : static_cast<std::uint32_t>(labels[j]);
    wrong_label += image[static_cast<std::size_t>(cell[j])].label != expected ? 1 : 0;
  }
  EXPECT_EQ(wrong_label, 0u);
}

TEST(PclInterop, ACloudIsWrittenAsPlyOrPcdOnly) {
  const CliResult r = runSlipfit("validate configs/sample_scan.yaml --set output.cloud=cloud.las");
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("'cloud.las' must end in .ply or .pcd"));
}

TEST(PclInterop, ATiledRunRefusesOutputsItDoesNotJoin) {
  for (const char* option :
       {"segments.pcd=s.pcd", "segments.local_copy=l.ply", "segments.segment_files=true"}) {
    const CliResult r =
        runSlipfit(std::string("validate configs/demo.yaml --set tiling.size=1 --set ") + option);
    EXPECT_EQ(r.code, 2) << option;
    EXPECT_THAT(r.err, HasSubstr(std::string(option).substr(0, std::string(option).find('=')) +
                                 " is not written by a tiled run"));
  }
}

}  // namespace
}  // namespace slipfit::testing
