#pragma once
/// \file Streaming a cloud into tiles (tile_grid.h): two reads of the input by row ranges
/// (CloudStream), one to count each tile's points, one to write them, shared among the ranks of a
/// run; memory is bounded by the write buffers, whatever the size of the cloud. Each tile is a
/// binary PLY of the input's fields plus `tile_row` (the point's row among the input's points with
/// finite coordinates, its row in segments.ply: the input's row when none is dropped; exact as a
/// double up to 2^53) and `tile_core`: 0 where a neighbour owns the point, 1 where this tile owns
/// it alone, 2 where it owns it and a neighbour holds it too (the shared points that the merge
/// compares).

#include "work_distribution.h"

#include "slipfit/pipeline/cloud_io.h"
#include "slipfit/tiling/tile_grid.h"
#include "slipfit/tiling/tile_tree.h"

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace slipfit::pipeline::tiling {

struct TileInfo {
  TileKey key;
  std::uint64_t points = 0;  ///< core and buffer
  std::uint64_t core = 0;    ///< points this tile owns
  std::uint64_t bytes = 0;   ///< the tile file's size as written
  /// "tile_<i>_<j>", and "tile_<i>_<j>_<level>" for a quarter of a split tile: the tile's file
  /// (.ply) and run directory.
  std::string name() const {
    return "tile_" + std::to_string(key.i) + "_" + std::to_string(key.j) +
           (key.level > 0 ? "_" + std::to_string(key.level) : "");
  }
};

/// What the tiling made, written last (manifest.yaml): a rerun with the same input and tiling
/// reuses the tiles.
struct TilingManifest {
  std::string input;
  std::uint64_t input_bytes = 0;
  std::int64_t input_mtime = 0;  ///< nanoseconds
  double size = 0.0, buffer = 0.0;
  std::uint64_t max_points = 0;  ///< the most core points of a tile that may be split; 0: none
  std::uint64_t points = 0;      ///< kept: each owned by exactly one tile
  std::uint64_t dropped = 0;     ///< non-finite coordinates (input.nan: skip)
  /// The x, y bounds of the kept points (for the merged report's global shift).
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  bool double_coordinates = false;
  /// The input's sensor (CloudStream::sensor: origin in the file's coordinates, orientation w, x,
  /// y, z) when it is a sensor's view: each tile is run as that sensor's view too.
  std::optional<std::array<double, 7>> sensor;
  std::vector<TileInfo> tiles;  ///< ascending by key; only tiles that own points

  /// The tiles' layout: the grid, and the splits that made these tiles.
  TileTree tree() const;
};

/// The input file's size and modification time, as the manifest records them.
void inputStamp(const std::string& path, std::uint64_t& bytes, std::int64_t& mtime);

/// Writes the tiles of \a input into \a dir (created) and returns the manifest (not yet saved).
/// With \a work, its ranks tile together (a collective call): each reads its share of the rows, a
/// contiguous range, their counts are added up, and each writes its rows of every tile at the
/// place the ranks before it leave; the tiles are the bytes one process writes, and every rank
/// returns the manifest. A failure on any rank is thrown on every rank.
/// A tile of \a grid whose core holds more than \a max_points points (0: no limit) is split into
/// quarters, and those again, while they stay wider than twice the buffer (tile_tree.h); each
/// split costs one more read of the input. \a progress(done, total) is called as rows are read
/// (the total grows by a read when tiles are split). Throws RunError naming the file and row
/// for unreadable input, a non-finite coordinate under NanPolicy::error, a coordinate outside the
/// grid, more than kMostTiles tiles or fewer than kFewestMeanTilePoints points a tile (before any
/// tile is written), and naming the tile for a failed
/// write.
TilingManifest writeTiles(const std::string& input, NanPolicy nan, const TileGrid& grid,
                          std::uint64_t max_points, const std::string& dir,
                          const std::function<void(std::uint64_t, std::uint64_t)>& progress,
                          WorkDistribution* work = nullptr);

/// tiling.size: auto, and what it was chosen from.
struct AutoTileSize {
  double size = 0.0;         ///< the edge chosen
  std::uint64_t points = 0;  ///< the input's points with finite coordinates
  double width = 0.0;        ///< their x extent
  double depth = 0.0;        ///< their y extent
  std::uint64_t target = 0;  ///< the points a tile of their mean density was sized to hold
};

/// The edge of a tile's core for tiling.size: auto — where a tile holds \a target of the input's
/// finite points (tiling.max_points, or its default when that is 0) spread evenly over their x-y
/// bounding box (w × d, d ≤ w): e² = w d target / N while e ≤ d, and past it, where a tile covers
/// e × d, e = w target / N (points along a line included); at least four times \a buffer when
/// one is given (so that a tile can be split once); rounded up to 1, 2 or 5 times a power of
/// ten. Denser parts than the mean are left to the splits of max_points. Reads the input once
/// (with \a work, shared among its ranks as writeTiles does); throws RunError as writeTiles does
/// for unreadable input, and when no point is finite.
AutoTileSize autoTileSize(const std::string& input, NanPolicy nan, std::uint64_t target,
                          double buffer,
                          const std::function<void(std::uint64_t, std::uint64_t)>& progress,
                          WorkDistribution* work = nullptr);

/// \a edge rounded up to 1, 2 or 5 times a power of ten.
double roundUpToOneTwoFive(double edge);

/// The most tiles a tiling may make, and the fewest points a tile may own on average: past
/// either the run is refused before any tile is written (a tile of a few points cannot be
/// segmented; its file and run cost the same as a full one's).
constexpr std::size_t kMostTiles = 100000;
constexpr double kFewestMeanTilePoints = 100.0;

/// "" when every tile file of \a manifest in \a dir has the size it was written with, else what
/// differs ("tile_0_1.ply holds 120 bytes, written 4096").
std::string verifyTiles(const TilingManifest& manifest, const std::string& dir);

/// manifest.yaml's text, and the manifest read back (false when \a path is missing or not one).
std::string manifestText(const TilingManifest& manifest);
bool readManifest(const std::string& path, TilingManifest& manifest);

}  // namespace slipfit::pipeline::tiling
