#pragma once
/// \file The phases of the segmentation kernel, numbered in the order they run. docs/THEORY.md §6
/// describes each under the same number; stages/src/segmentation/phases/ holds one file per group.

#include <string_view>

namespace slipfit {

enum class SegmentationPhase {
  /// Noise σ̂ (on each point's own sheet where a thin wall puts both faces in its neighborhood),
  /// spacing, a quantized depth axis → each point's distance tolerance. phases/scale.cpp
  estimate_scale = 1,
  /// Seeds where the neighbors agree on the local slippage type, growth bounded by the region's
  /// own fit, the type re-chosen on the grown region. phases/seeding.cpp
  grow_slippage_seeds = 2,
  /// A second round from the points still free (small faces whose neighborhoods all straddle an
  /// edge), with the simplest adequate type of the seed's neighbors; a seed's free neighbors must
  /// be sampled like the regions around them; on a thin wall, the seed's own sheet of its 2-ring.
  /// phases/seeding.cpp
  grow_free_seeds = 3,
  /// Adjacent regions whose union one primitive fits about as well. phases/merging.cpp
  merge_regions = 4,
  /// A narrow region's type re-chosen on the points of its neighbors it contests (the band of a
  /// tangent fillet that read as a plane). phases/types.cpp
  revise_types = 5,
  /// Two planes meeting at a crease whose points a fillet between them explains better give the
  /// fillet's points to a cylinder. phases/fillets.cpp
  recover_fillets = 6,
  /// Points that a neighboring segment's primitive explains better move; edge points go to the
  /// smaller segment. phases/boundaries.cpp
  refine_boundaries = 7,
  /// Free points at creases join the nearest adjacent primitive within tolerance.
  /// phases/boundaries.cpp
  join_creases = 8,
  /// A patch of free points that no adjacent primitive explains is a face too small to seed,
  /// fitted with the edge points it shares when it is sampled like the regions around it.
  /// phases/small_faces.cpp
  recover_small_faces = 9,
  /// A region that a neighbor four times its size explains as well as that neighbor's own points
  /// joins it. phases/merging.cpp
  absorb_fragments = 10,
  /// Adjacent regions merge again, now that boundaries have settled, when one primitive of the
  /// larger's type is the better model of their union by BIC. phases/merging.cpp
  merge_settled_regions = 11,
  /// Regions that fill their tolerance slab like random points, or lie on one level of a
  /// quantized axis, are dropped. phases/finalize.cpp
  drop_non_surfaces = 12,
  /// On a sensor's frame, surfaces that an occluder cut apart (a floor either side of a table)
  /// join when one primitive of their type is the better model of both by BIC and explains each
  /// within its noise. phases/merging.cpp
  join_occluded_pieces = 13,
};

/// The first and last phase, for iterating over all of them.
constexpr SegmentationPhase kFirstSegmentationPhase = SegmentationPhase::estimate_scale;
constexpr SegmentationPhase kLastSegmentationPhase = SegmentationPhase::join_occluded_pieces;

/// The phase's name as in the code ("estimate_scale"), for reports and progress.
std::string_view phaseName(SegmentationPhase phase);

}  // namespace slipfit
