// The filter stages (crop, voxel_grid, outlier_removal) as a user runs them: each keeps exactly the
// points its PCL filter selects, with their fields, reports the count, and refuses to run on an
// analysis sample.

#include "run_cli.h"

#include "slipfit/pipeline/cloud_io.h"
#include "slipfit/sampling/random_vector.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <tuple>

namespace slipfit::testing {
namespace {

using ::testing::HasSubstr;

/// An ascii PLY of \a points rows "x y z intensity".
std::string plyOf(const std::vector<Eigen::Vector3f>& points) {
  std::ostringstream s;
  s << "ply\nformat ascii 1.0\nelement vertex " << points.size()
    << "\nproperty float x\nproperty float y\nproperty float z\nproperty float intensity\n"
       "end_header\n";
  s.precision(9);
  for (std::size_t i = 0; i < points.size(); ++i)
    s << points[i].x() << " " << points[i].y() << " " << points[i].z() << " " << i << "\n";
  return s.str();
}

/// A 1 × 1 plane z = 0 of 10,000 random points and 100 points scattered 0.5–1.5 above it.
std::vector<Eigen::Vector3f> planeWithOutliers(std::size_t& outliers) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Eigen::Vector3f> p;
  for (int i = 0; i < 10000; ++i) {
    const Eigen::Vector2f w = randomVector<2>(u, rng);
    p.emplace_back(w(0), w(1), 0.0f);
  }
  outliers = 100;
  for (std::size_t i = 0; i < outliers; ++i)
    p.emplace_back(randomVector<3>(u, rng) + Eigen::Vector3f(0.0f, 0.0f, 0.5f));
  return p;
}

struct Filtered {
  CliResult run;
  pipeline::PointData data;
};

/// Runs \a stages (YAML flow list) on \a points and reads the written cloud.
Filtered runFilter(const std::string& name, const std::vector<Eigen::Vector3f>& points,
                   const std::string& stages) {
  const std::string in = scratchFile(name + ".ply", plyOf(points));
  const std::string out = scratchDir(name);
  const std::string config =
      scratchFile(name + ".yaml", "input: {path: " + in + "}\nstages: " + stages +
                                      "\noutput: {dir: " + out + ", cloud: cloud.ply}\n");
  Filtered f;
  f.run = runSlipfit("run " + config);
  if (f.run.code == 0)
    f.data = pipeline::readCloud(out + "/cloud.ply", pipeline::NanPolicy::error);
  return f;
}

std::vector<double> intensity(const pipeline::PointData& d) {
  return d.numericField("intensity");
}

TEST(FilterStages, CropKeepsExactlyThePointsWithinItsLimits) {
  std::size_t outliers = 0;
  const auto points = planeWithOutliers(outliers);
  // PassThrough on z: the plane only.
  const Filtered z = runFilter("crop_z", points, "[{type: crop, field: z, min: -0.1, max: 0.1}]");
  ASSERT_EQ(z.run.code, 0) << z.run.err;
  EXPECT_EQ(z.data.size(), 10000u);
  EXPECT_THAT(z.run.out, HasSubstr("crop: 10000 of 10100 points kept, 100 dropped (kept z in "
                                   "[-0.1, 0.1])"));
  // Each kept point is the input point of its intensity (its index): fields travel with it.
  const std::vector<double> id = intensity(z.data);
  for (std::size_t k = 0; k < z.data.size(); ++k)
    ASSERT_EQ((*z.data.cloud)[k].getVector3fMap(), points[static_cast<std::size_t>(id[k])]);
  // CropBox, negative: the points outside the box [0, 0.5]² × [−1, 2].
  const Filtered box =
      runFilter("crop_box", points,
                "[{type: crop, box_min: [0, 0, -1], box_max: [0.5, 0.5, 2], negative: true}]");
  ASSERT_EQ(box.run.code, 0) << box.run.err;
  std::size_t outside = 0;
  for (const auto& p : points)
    outside += (p.x() <= 0.5f && p.y() <= 0.5f) ? 0 : 1;
  EXPECT_EQ(box.data.size(), outside);
  for (const auto& p : box.data.cloud->points)
    EXPECT_FALSE(p.x <= 0.5f && p.y <= 0.5f);
  // Issue 38's messages: a one-sided limit says its side (it printed "z in [-3.40282e+38, 0.1]"),
  // and a box corner keeps its digits (it printed "[500000 5.4e+06 0]").
  const Filtered below = runFilter("crop_below", points, "[{type: crop, field: z, max: 0.1}]");
  ASSERT_EQ(below.run.code, 0) << below.run.err;
  EXPECT_THAT(below.run.out, HasSubstr("(kept z <= 0.1)"));
  const Filtered far =
      runFilter("crop_far", points,
                "[{type: crop, box_min: [-5400000, -1, -1], box_max: [500000.25, 1, 1]}]");
  ASSERT_EQ(far.run.code, 0) << far.run.err;
  EXPECT_THAT(far.run.out,
              HasSubstr("(kept inside the box (-5400000, -1, -1) – (500000.25, 1, 1))"));
}

TEST(FilterStages, VoxelGridKeepsOnePointPerOccupiedVoxel) {
  std::size_t outliers = 0;
  const auto points = planeWithOutliers(outliers);
  const float leaf = 0.05f;
  std::set<std::tuple<int, int, int>> occupied;
  const auto key = [&](const Eigen::Vector3f& p) {
    return std::make_tuple(int(std::floor(p.x() / leaf)), int(std::floor(p.y() / leaf)),
                           int(std::floor(p.z() / leaf)));
  };
  for (const auto& p : points)
    occupied.insert(key(p));
  for (const std::string method : {"uniform", "centroid"}) {
    const Filtered f = runFilter("voxel_" + method, points,
                                 "[{type: voxel_grid, leaf: 0.05, method: " + method + "}]");
    ASSERT_EQ(f.run.code, 0) << f.run.err;
    EXPECT_EQ(f.data.size(), occupied.size()) << method;
    std::set<std::tuple<int, int, int>> seen;
    const std::vector<double> id = intensity(f.data);
    for (std::size_t k = 0; k < f.data.size(); ++k) {
      const Eigen::Vector3f p = (*f.data.cloud)[k].getVector3fMap();
      // uniform: an input point; centroid: inside the voxel of the input point it stands for.
      const Eigen::Vector3f source = points[static_cast<std::size_t>(id[k])];
      if (method == "uniform")
        EXPECT_EQ(p, source);
      else
        EXPECT_EQ(key(p), key(source)) << k;
      seen.insert(key(source));
    }
    EXPECT_EQ(seen.size(), f.data.size()) << method << ": two points of one voxel";
  }
}

TEST(FilterStages, OutlierRemovalDropsTheScatteredPoints) {
  std::size_t outliers = 0;
  const auto points = planeWithOutliers(outliers);
  for (const std::string stage :
       {"{type: outlier_removal, k: 20, stddev: 2}",
        "{type: outlier_removal, method: radius, radius: 0.05, min_neighbors: 5}"}) {
    const Filtered f = runFilter("outliers", points, "[" + stage + "]");
    ASSERT_EQ(f.run.code, 0) << f.run.err;
    std::size_t plane = 0, above = 0;
    for (const auto& p : f.data.cloud->points)
      (std::abs(p.z) < 1e-6f ? plane : above) += 1;
    std::cout << stage << ": " << plane << " plane points and " << above << " outliers kept\n";
    EXPECT_EQ(above, 0u) << stage;
    EXPECT_EQ(plane, 10000u) << stage;  // measured: every plane point kept
  }
}

TEST(FilterStages, FiltersRefuseAnAnalysisSampleAndBadLimits) {
  std::size_t outliers = 0;
  const auto points = planeWithOutliers(outliers);
  const Filtered late = runFilter(
      "late", points, "[{type: subsample, points: 1000}, {type: crop, field: z, max: 1}]");
  EXPECT_EQ(late.run.code, 1);
  EXPECT_THAT(late.run.err, HasSubstr("place this stage before the subsample stage"));
  const Filtered none = runFilter("none", points, "[{type: crop, field: z, min: 5}]");
  EXPECT_EQ(none.run.code, 1);
  EXPECT_THAT(none.run.err, HasSubstr("no point of the 10100 is kept"));
  for (const auto& [stages, message] : std::vector<std::pair<std::string, std::string>>{
           {"[{type: crop}]", "give field with min/max, or box_min and box_max"},
           {"[{type: crop, field: z}]", "field needs min and/or max"},
           {"[{type: crop, field: z, min: 2, max: 1}]", "min must not exceed max"},
           {"[{type: crop, box_min: [0, 0, 0], box_max: [1, 0, 1]}]", "box_min must be below"},
           {"[{type: voxel_grid}]", "leaf"},
           {"[{type: voxel_grid, leaf: 1e-9}]", "more than PCL's grid can index"},
           {"[{type: outlier_removal, method: radius}]", "method radius needs radius"}}) {
    const Filtered f = runFilter("bad", points, stages);
    EXPECT_NE(f.run.code, 0) << stages;
    EXPECT_THAT(f.run.err, HasSubstr(message)) << stages;
    EXPECT_EQ(std::count(f.run.err.begin(), f.run.err.end(), '\n'), 1) << f.run.err;
  }
}

}  // namespace
}  // namespace slipfit::testing
