#include "slipfit/segmentation/segmentation_kernel.h"

#include "phases/phases.h"

#include <algorithm>
#include <chrono>

namespace slipfit {

std::string_view phaseName(SegmentationPhase phase) {
  switch (phase) {
    case SegmentationPhase::estimate_scale:
      return "estimate_scale";
    case SegmentationPhase::grow_slippage_seeds:
      return "grow_slippage_seeds";
    case SegmentationPhase::grow_free_seeds:
      return "grow_free_seeds";
    case SegmentationPhase::merge_regions:
      return "merge_regions";
    case SegmentationPhase::revise_types:
      return "revise_types";
    case SegmentationPhase::recover_fillets:
      return "recover_fillets";
    case SegmentationPhase::refine_boundaries:
      return "refine_boundaries";
    case SegmentationPhase::join_creases:
      return "join_creases";
    case SegmentationPhase::recover_small_faces:
      return "recover_small_faces";
    case SegmentationPhase::absorb_fragments:
      return "absorb_fragments";
    case SegmentationPhase::merge_settled_regions:
      return "merge_settled_regions";
    case SegmentationPhase::join_occluded_pieces:
      return "join_occluded_pieces";
    case SegmentationPhase::drop_non_surfaces:
      return "drop_non_surfaces";
  }
  return "unknown";
}

SegmentationKernel::SegmentationKernel(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                       const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                                       const Neighborhoods& neighborhoods,
                                       const std::vector<SlippageType>& local_types,
                                       const SegmentationParameters& parameters)
    : state_(points, normals, neighborhoods, local_types, parameters) {}

void SegmentationKernel::run(Phase phase) {
  if (on_phase_)
    on_phase_(phaseName(phase));
  const auto start = std::chrono::steady_clock::now();
  runPhase(phase);
  state_.result.timings.push_back(
      {std::string(phaseName(phase)),
       std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()});
}

void SegmentationKernel::runPhase(Phase phase) {
  SegmentationState& s = state_;
  switch (phase) {
    case Phase::estimate_scale:
      return phases::estimateScale(s);
    case Phase::grow_slippage_seeds:
      return phases::growSlippageSeeds(s);
    case Phase::grow_free_seeds:
      return phases::growFreeSeeds(s);
    case Phase::merge_regions:
      return phases::mergeRegions(s);
    case Phase::revise_types:
      return phases::reviseTypes(s);
    case Phase::recover_fillets:
      return phases::recoverFillets(s);
    case Phase::refine_boundaries:
      return phases::refineBoundaries(s);
    case Phase::join_creases:
      return phases::joinCreases(s);
    case Phase::recover_small_faces:
      return phases::recoverSmallFaces(s);
    case Phase::absorb_fragments:
      return phases::absorbFragments(s);
    case Phase::merge_settled_regions:
      return phases::mergeSettledRegions(s);
    case Phase::join_occluded_pieces:
      return phases::joinOccludedPieces(s);
    case Phase::drop_non_surfaces:
      return phases::dropNonSurfaces(s);
  }
}

void SegmentationKernel::runPhases(Phase first, Phase last, std::initializer_list<Phase> skip) {
  for (int k = static_cast<int>(first); k <= static_cast<int>(last); ++k) {
    const auto phase = static_cast<Phase>(k);
    if (std::find(skip.begin(), skip.end(), phase) == skip.end())
      run(phase);
  }
}

SegmentationResult SegmentationKernel::finalize() {
  if (on_phase_)
    on_phase_("finalize");
  const auto start = std::chrono::steady_clock::now();
  SegmentationResult result = phases::finalize(state_);
  result.timings.push_back(
      {"finalize",
       std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()});
  return result;
}

}  // namespace slipfit
