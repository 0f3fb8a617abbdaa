#pragma once
/// \file The merge of a tiled run: segments of neighbouring tiles joined on their shared buffer
/// points (segment_joining.h), each joined segment refitted on the union of its pieces' samples,
/// and segments.ply (in the input's order) and primitives.yaml written as streams, each point from
/// the one tile that owns it (docs/TILING.md).

#include "tiler.h"
#include "work_distribution.h"

#include "slipfit/fitting/weighted_fit.h"
#include "slipfit/pipeline/output_files.h"
#include "slipfit/pipeline/tile_roles.h"
#include "slipfit/render/splat_renderer.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace slipfit::pipeline::tiling {

struct MergeSummary {
  std::size_t segments = 0;    ///< of the whole cloud
  std::size_t pieces = 0;      ///< per-tile segments that own points
  std::size_t joins = 0;       ///< pairs of pieces joined across tiles
  std::uint64_t points = 0;    ///< written
  std::uint64_t assigned = 0;  ///< of those, in a segment
};

/// The picture of the merged segments draws at most kRenderedPoints of them (every k-th written).
constexpr std::uint64_t kRenderedPoints = 2000000;

/// The fit of a joined segment's samples (\a points relative to the merge's origin, \a normals,
/// \a weights): fitPrimitive's closed form and refinement, or where that fails \a start — the fit
/// of the segment's largest piece — refined on them (fitFrom). The closed forms of cones,
/// cylinders and tori read the normals; on a dense tile analysed at a coarse voxel they can be
/// too noisy for them (a 20 M-point scene's cone: its apex from the normals at z 0.375, not 1).
FitResult refitJoined(PrimitiveType type, const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                      const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                      const Eigen::Ref<const Eigen::VectorXd>& weights,
                      const std::optional<Primitive>& start);

/// Where a merge's time went (seconds of wall on this rank).
struct MergeTimes {
  double joins = 0.0;     ///< reading the tiles' segments and shared points, the joins (shared)
  double segments = 0.0;  ///< numbering the joined segments (every rank alike)
  double refits = 0.0;    ///< refits of the joined segments (shared)
  double rows = 0.0;      ///< segments.ply's rows (shared)
  double leader = 0.0;    ///< the leader alone: LAS, picture, primitives.yaml
};

/// The merge's tiles of each of \a ranks: rank r takes tiles [first[r], first[r + 1]) of \a m, a
/// run of them holding about its share of the points owned.
std::vector<std::size_t> mergeShares(const TilingManifest& m, int ranks);

/// Merges the finished runs of \a manifest's tiles (their files in \a tiles_dir) in \a runs_dir
/// (one directory per tile) into \a files (the report, segments.ply and, when named,
/// segments.las: written from the merged segments.ply's rows, segmentsLas), and the picture when
/// \a render is given, added to \a outputs (committed by the caller). A collective call of
/// \a work's ranks: each reads its share of the tiles (mergeShares), finds their joins, refits
/// the joined segments whose first tile is one of them and writes their rows of segments.ply;
/// the leader (the one with \a outputs; nullptr on the others) adds up what they found and
/// writes the rest. Every rank must see the output directory. Up to \a workers tiles are read
/// and written at a time on each rank; the outputs depend neither on it nor on the ranks. A
/// failure on any rank is thrown on every rank. \a times, when given, receives this rank's
/// times.
MergeSummary mergeTiles(const TilingManifest& manifest, const std::string& tiles_dir,
                        const std::string& runs_dir, const JoinedAcrossTiles::Files& files,
                        const RenderRequest* render, int workers, OutputFiles* outputs,
                        WorkDistribution& work, MergeTimes* times = nullptr);

}  // namespace slipfit::pipeline::tiling
