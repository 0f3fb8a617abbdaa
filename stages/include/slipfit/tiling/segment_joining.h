#pragma once
/// \file Joining the segments of neighbouring tiles (tile_grid.h) into the segments of the whole
/// cloud. Two tiles share the points of their overlapping buffers; a shape crossing their border
/// is segmented in both, and on the shared points the two segments hold the same points. Segment
/// a of tile A and segment b of tile B are joined when they have the same primitive type and
/// hold mostly the same shared points (docs/THEORY.md §7): the points labelled both a and b are
/// at least `min_agreement` of the shared points of the smaller of the two (so that a shape cut
/// into pieces in one tile joins each piece) and at least `min_shared` points.
/// Joining is transitive (disjoint sets), so a shape across many tiles becomes one segment.

#include <cstddef>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

namespace slipfit {

/// How the segments of two tiles label the points they share.
struct OverlapCounts {
  std::uint64_t shared = 0;  ///< points in both tiles
  /// (label in A, label in B) → shared points labelled so; only labels ≥ 0.
  std::map<std::pair<std::int32_t, std::int32_t>, std::uint64_t> both;
  std::map<std::int32_t, std::uint64_t> in_a, in_b;  ///< shared points by label ≥ 0 in A, in B
};

/// Counts the shared points of two tiles from their rows (the points' indices in the input,
/// ascending within each tile) and labels (−1: unassigned). Throws std::invalid_argument when the
/// rows are not strictly ascending or the lengths differ.
OverlapCounts countOverlap(const std::vector<std::uint64_t>& rows_a,
                           const std::vector<std::int32_t>& labels_a,
                           const std::vector<std::uint64_t>& rows_b,
                           const std::vector<std::int32_t>& labels_b);

struct JoinParameters {
  double min_agreement = 0.5;     ///< fraction of the smaller segment's shared points
  std::uint64_t min_shared = 10;  ///< at least this many points held by both
};

/// The pairs (label in A, label in B) to join, ascending. \a type_a / \a type_b: the primitive
/// type of each label (indexed by label; a label beyond the vector never joins).
std::vector<std::pair<std::int32_t, std::int32_t>> segmentsToJoin(
    const OverlapCounts& counts, const std::vector<int>& type_a, const std::vector<int>& type_b,
    const JoinParameters& parameters = {});

/// Disjoint sets over 0 … n−1 (path halving); the representative of a set is
/// its smallest member, so the result does not depend on the order of the joins.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n);
  std::size_t find(std::size_t x);
  void join(std::size_t a, std::size_t b);

 private:
  std::vector<std::size_t> parent_;
};

}  // namespace slipfit
