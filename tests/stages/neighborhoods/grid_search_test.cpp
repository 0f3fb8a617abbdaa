#include "slipfit/neighborhoods/grid_search.h"
#include "slipfit/core/exceptions.h"
#include "slipfit/neighborhoods/nanoflann_search.h"
#include "slipfit/neighborhoods/neighborhood_selection.h"

#include <gtest/gtest.h>

#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>

namespace slipfit {
namespace {

using XyzCloud = pcl::PointCloud<pcl::PointXYZ>;

// A pinhole camera (f = 200 px, 120 × 90 pixels) looking along +z at a wall at depth
// z = 2 + 0.6 x + 0.25 y (tilted about 33° from the view axis) with a box face at z = 0.9 in
// front of its middle (a depth discontinuity of about 1.1 m). Every 7th pixel of one column band
// is a hole. Only the finite returns are kept, each with its pixel.
struct Frame {
  XyzCloud::Ptr cloud{new XyzCloud};
  PixelGrid grid;
  std::vector<char> box;  // per point: on the box face
};

Frame frame() {
  Frame f;
  f.grid.width = 120;
  f.grid.height = 90;
  const double focal = 200.0, cu = 59.5, cv = 44.5;
  for (int v = 0; v < 90; ++v)
    for (int u = 0; u < 120; ++u) {
      if (u == 30 && v % 7 == 0)
        continue;                                               // holes
      const double a = (u - cu) / focal, b = (v - cv) / focal;  // ray (a, b, 1)
      const bool on_box = std::abs(u - cu) < 20 && std::abs(v - cv) < 15;
      // The wall: z = 2 + 0.6 a z + 0.25 b z along the ray.
      const double z = on_box ? 0.9 : 2.0 / (1.0 - 0.6 * a - 0.25 * b);
      f.cloud->push_back(pcl::PointXYZ(static_cast<float>(a * z), static_cast<float>(b * z),
                                       static_cast<float>(z)));
      f.grid.cells.push_back(v * 120 + u);
      f.box.push_back(on_box ? 1 : 0);
    }
  return f;
}

// The point's 5 × 5 window lies on one surface, inside the image and clear of the holes.
bool interior(const Frame& f, std::size_t i) {
  const int cell = f.grid.cells[i], u = cell % 120, v = cell / 120;
  if (u < 3 || u > 116 || v < 3 || v > 86 || std::abs(u - 30) <= 3)
    return false;
  const bool box = f.box[i];
  for (int dv = -3; dv <= 3; ++dv)
    for (int du = -3; du <= 3; ++du) {
      const bool other = std::abs(u + du - 59.5) < 20 && std::abs(v + dv - 44.5) < 15;
      if (other != box)
        return false;
    }
  return true;
}

// The frame with both searches bound to it.
struct GridAndTree {
  Frame frame = slipfit::frame();
  GridSearch<pcl::PointXYZ> grid{frame.grid};
  NanoflannSearch<pcl::PointXYZ> tree{true};
  GridAndTree() {
    grid.setInputCloud(frame.cloud);
    tree.setInputCloud(frame.cloud);
  }
};

TEST(GridSearch, KnnInsideASmoothSurfaceIsTheKdTreesAnswer) {
  const GridAndTree s;
  const Frame& f = s.frame;
  const GridSearch<pcl::PointXYZ>& grid = s.grid;
  const NanoflannSearch<pcl::PointXYZ>& tree = s.tree;
  pcl::Indices a, b;
  std::vector<float> da, db;
  std::size_t compared = 0;
  for (std::size_t i = 0; i < f.cloud->size(); ++i) {
    if (!interior(f, i))
      continue;
    ++compared;
    const auto index = static_cast<pcl::index_t>(i);
    ASSERT_EQ(grid.nearestKSearch(*f.cloud, index, 12, a, da), 12);
    tree.nearestKSearch(*f.cloud, index, 12, b, db);
    // The same distances, nearest first; the same set of points (ties may swap places).
    for (std::size_t j = 0; j < 12; ++j)
      ASSERT_NEAR(da[j], db[j], 1e-7f * (1.0f + db[j])) << "point " << i << ", rank " << j;
    ASSERT_EQ(a[0], index);
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    ASSERT_EQ(a, b) << "point " << i;
  }
  EXPECT_GT(compared, 5000u);
}

TEST(GridSearch, RadiusSearchFindsEveryPointTheKdTreeFindsOnOneSurface) {
  const GridAndTree s;
  const Frame& f = s.frame;
  const GridSearch<pcl::PointXYZ>& grid = s.grid;
  const NanoflannSearch<pcl::PointXYZ>& tree = s.tree;
  pcl::Indices a, b;
  std::vector<float> da, db;
  // 4 pixel pitches on the wall (a pitch is about z / f = 1 cm across the ray).
  const double radius = 0.04;
  for (std::size_t i = 0; i < f.cloud->size(); i += 7) {
    if (!interior(f, i))
      continue;
    const auto index = static_cast<pcl::index_t>(i);
    grid.radiusSearch(*f.cloud, index, radius, a, da);
    tree.radiusSearch(*f.cloud, index, radius, b, db);
    ASSERT_TRUE(std::is_sorted(da.begin(), da.end()));
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    ASSERT_EQ(a, b) << "point " << i;
  }
}

TEST(GridSearch, NeighborsNeverCrossTheDepthDiscontinuity) {
  // The box's edge pixels have wall pixels in their window, 1.1 m behind: none is a neighbor.
  const Frame f = frame();
  GridSearch<pcl::PointXYZ> grid(f.grid);
  grid.setInputCloud(f.cloud);
  pcl::Indices a;
  std::vector<float> d;
  std::size_t edge = 0;
  for (std::size_t i = 0; i < f.cloud->size(); ++i) {
    if (!f.box[i] || interior(f, i))
      continue;
    ++edge;
    grid.nearestKSearch(*f.cloud, static_cast<pcl::index_t>(i), 12, a, d);
    for (const auto j : a)
      ASSERT_TRUE(f.box[static_cast<std::size_t>(j)]) << "box point " << i << " took " << j;
  }
  EXPECT_GT(edge, 100u);
}

TEST(GridSearch, NeighborhoodSelectionUsesTheGridWithoutATree) {
  const Frame f = frame();
  NeighborhoodSelection<pcl::PointXYZ> selection;
  NeighborhoodParameters p;
  p.k = 12;
  selection.setParameters(p);
  selection.setInputCloud(f.cloud);
  selection.setSearchMethod(std::make_shared<GridSearch<pcl::PointXYZ>>(f.grid));
  Neighborhoods hoods;
  selection.compute(hoods);
  EXPECT_TRUE(selection.statistics().pixel_grid);
  EXPECT_EQ(selection.statistics().tree_builds, 0u);
  ASSERT_EQ(hoods.size(), f.cloud->size());
  for (std::size_t i = 0; i < hoods.size(); ++i) {
    ASSERT_EQ(hoods[i].size(), 12u);
    ASSERT_EQ(hoods[i][0], static_cast<pcl::index_t>(i));
  }
}

TEST(GridSearch, RefusesABadGridAndQueriesItCannotAnswer) {
  const Frame f = frame();
  auto expectRefused = [&](PixelGrid g, const std::string& words) {
    GridSearch<pcl::PointXYZ> grid(std::move(g));
    try {
      grid.setInputCloud(f.cloud);
      ADD_FAILURE() << "accepted a grid that should fail with '" << words << "'";
    } catch (const InvalidParameterError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  PixelGrid outside = f.grid;
  outside.cells[5] = 120 * 90;
  expectRefused(outside, "point 5's cell 10800 lies outside the 120 x 90 image");
  PixelGrid twice = f.grid;
  twice.cells[9] = twice.cells[8];
  expectRefused(twice, "holds two points (the second is point 9)");
  PixelGrid short_grid = f.grid;
  short_grid.cells.pop_back();
  expectRefused(short_grid, "cells for a cloud of");

  GridSearch<pcl::PointXYZ> grid(f.grid);
  grid.setInputCloud(f.cloud);
  pcl::Indices ind;
  std::vector<float> d;
  EXPECT_THROW(grid.nearestKSearch(pcl::PointXYZ(0, 0, 1), 3, ind, d), InvalidParameterError);
  const XyzCloud other = *f.cloud;
  EXPECT_THROW(grid.radiusSearch(other, 0, 0.1, ind, d), InvalidParameterError);
}

}  // namespace
}  // namespace slipfit
