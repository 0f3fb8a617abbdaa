// tiling.size: auto (autoTileSize, tiling/tiler.h): the edge at which a tile of the input's mean
// density over its x-y extent holds the target count, rounded up to 1, 2 or 5 times a power of
// ten, computed here from the points written rather than read back from the program.
#include "run_cli.h"
#include "tiling/tiler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

namespace slipfit::testing {
namespace {

using pipeline::NanPolicy;
using pipeline::tiling::autoTileSize;
using pipeline::tiling::AutoTileSize;
using pipeline::tiling::roundUpToOneTwoFive;

/// A binary PLY of x y z floats.
std::string writeCloud(const std::string& name, const std::vector<float>& xyz) {
  const std::string dir = processScratch() + "/tile_size";
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/" + name + ".ply";
  std::ofstream out(path, std::ios::binary);
  out << "ply\nformat binary_little_endian 1.0\nelement vertex " << xyz.size() / 3
      << "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  out.write(reinterpret_cast<const char*>(xyz.data()),
            static_cast<std::streamsize>(xyz.size() * sizeof(float)));
  return path;
}

TEST(TileSize, RoundsUpToOneTwoOrFiveTimesAPowerOfTen) {
  EXPECT_EQ(roundUpToOneTwoFive(1.0), 1.0);
  EXPECT_EQ(roundUpToOneTwoFive(1.0001), 2.0);
  EXPECT_EQ(roundUpToOneTwoFive(2.0), 2.0);
  EXPECT_EQ(roundUpToOneTwoFive(2.5), 5.0);
  EXPECT_EQ(roundUpToOneTwoFive(7.0), 10.0);
  EXPECT_EQ(roundUpToOneTwoFive(19.98), 20.0);
  EXPECT_EQ(roundUpToOneTwoFive(5000.0), 5000.0);
  EXPECT_DOUBLE_EQ(roundUpToOneTwoFive(0.013), 0.02);
  EXPECT_DOUBLE_EQ(roundUpToOneTwoFive(0.3), 0.5);
}

// 200 × 100 points on a 0.1 grid over 19.9 × 9.9: a tile of 2,000 of them has an edge of
// √(19.9 · 9.9 · 2000 / 20000) = 4.44, rounded up to 5 (a 5 × 5 tile of that grid holds 2,500);
// the non-finite point is not counted.
TEST(TileSize, ATileOfTheMeanDensityHoldsTheTarget) {
  std::vector<float> xyz;
  for (int i = 0; i < 200; ++i)
    for (int j = 0; j < 100; ++j)
      xyz.insert(xyz.end(), {0.1f * static_cast<float>(i), 0.1f * static_cast<float>(j), 1.0f});
  xyz.insert(xyz.end(), {std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f});
  const std::string path = writeCloud("plane", xyz);
  const AutoTileSize a = autoTileSize(path, NanPolicy::skip, 2000, 0.0, {});
  EXPECT_EQ(a.points, 20000u);
  EXPECT_NEAR(a.width, 19.9, 1e-5);
  EXPECT_NEAR(a.depth, 9.9, 1e-5);
  EXPECT_EQ(a.target, 2000u);
  EXPECT_EQ(a.size, 5.0);
  // A buffer of 3 asks for an edge of at least 12, so that a tile's quarters (6) are still wider
  // than twice the buffer: 20.
  EXPECT_EQ(autoTileSize(path, NanPolicy::skip, 2000, 3.0, {}).size, 20.0);
  // Past the narrow side (9.9) a tile covers e × 9.9 of the extent: it holds 50,000 at e =
  // 19.9 · 50000 / 20000 = 49.75, rounded up to 50 — one tile for all, fewer than the target.
  EXPECT_EQ(autoTileSize(path, NanPolicy::skip, 50000, 0.0, {}).size, 50.0);
}

// Points along a line have no area: a tile holds the target along the longer side
// (99.9 · 100 / 1000 = 9.99, rounded up to 10). All at one x, y: any edge holds them; 1, or four
// buffers.
TEST(TileSize, PointsOnALineOrAtOnePlaceGetAnEdgeToo) {
  std::vector<float> line, pole;
  for (int i = 0; i < 1000; ++i) {
    line.insert(line.end(), {0.1f * static_cast<float>(i) + 0.05f, 3.0f, 0.0f});
    pole.insert(pole.end(), {2.0f, 3.0f, 0.01f * static_cast<float>(i)});
  }
  const AutoTileSize a = autoTileSize(writeCloud("line", line), NanPolicy::skip, 100, 0.0, {});
  EXPECT_NEAR(a.width, 99.9, 1e-4);
  EXPECT_EQ(a.depth, 0.0);
  EXPECT_EQ(a.size, 10.0);
  const std::string p = writeCloud("pole", pole);
  EXPECT_EQ(autoTileSize(p, NanPolicy::skip, 100, 0.0, {}).size, 1.0);
  EXPECT_EQ(autoTileSize(p, NanPolicy::skip, 100, 0.5, {}).size, 2.0);
}

TEST(TileSize, AnInputWithoutAFinitePointIsRefusedByName) {
  const std::string path =
      writeCloud("nothing", {std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f,
                             std::numeric_limits<float>::infinity(), 1.0f, 1.0f});
  try {
    autoTileSize(path, NanPolicy::skip, 100, 0.0, {});
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_EQ(std::string(e.what()),
              "input '" + path + "': no point has finite coordinates to tile");
  }
}

}  // namespace
}  // namespace slipfit::testing
