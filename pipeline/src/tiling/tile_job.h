#pragma once
/// \file One tile of a tiled run: the unchanged pipeline on the tile's file, then what the merge
/// needs from its segments, written next to its outputs:
/// - labels.bin: the number of points the tile owns, and for every point it shares with a
///   neighbour (tile_core 0 or 2) its input row, segment label and whether the tile owns it;
/// - segments.yaml: per label its primitive type, core points, inlier distance, seed type;
/// - samples.bin: per label up to kSamplesPerSegment of its core points (every k-th, in row
///   order) with normals, for the refit of the joined segments;
/// - done: written last, with the size and digest of each of those files and of the tile's
///   segments.ply and primitives.yaml; a tile whose files verify against it is not run again
///   (resume), one that does not is run again.

#include "slipfit/pipeline/cloud_stream.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace slipfit::pipeline::tiling {

constexpr std::uint64_t kSamplesPerSegment = 4000;

/// What labels.bin holds: the points the tile shares with its neighbours.
struct TileLabels {
  std::uint64_t owned = 0;           ///< points the tile owns, shared or not
  std::vector<std::uint64_t> rows;   ///< ascending
  std::vector<std::int32_t> labels;  ///< −1: unassigned
  std::vector<std::uint8_t> core;    ///< 1: the tile owns the point
};

/// What segments.yaml holds, per label of the tile.
struct TileSegment {
  int type = -1;  ///< PrimitiveType
  std::uint64_t core_points = 0;
  double inlier_distance = 0.0;
  std::string seed_slippage_type;
};

/// samples.bin: points of one label, each standing for `weight` core points.
struct TileSamples {
  std::vector<std::int32_t> labels;
  Eigen::Matrix3Xd points, normals;  ///< in the input's frame
  std::vector<double> weights;
};

/// Extracts labels.bin, segments.yaml and samples.bin from the tile's segments.ply and
/// primitives.yaml in \a run_dir, then writes `done`. Throws RunError naming a missing or
/// unreadable file.
void summariseTile(const std::string& run_dir, const std::string& segments_ply,
                   const std::string& primitives_yaml);

TileLabels readTileLabels(const std::string& run_dir);
std::vector<TileSegment> readTileSegments(const std::string& run_dir);
TileSamples readTileSamples(const std::string& run_dir);

/// Whether the tile's run finished and its files are the ones it wrote (sizes and digests as
/// `done` records them). False with \a why empty when there is no `done` (the run did not end),
/// false with \a why saying which file differs when they do not verify.
bool tileDone(const std::string& run_dir, std::string& why);

}  // namespace slipfit::pipeline::tiling
