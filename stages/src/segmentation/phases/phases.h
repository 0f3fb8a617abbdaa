#pragma once
/// \file The segmentation phases, each a function of the shared state (segmentation_state.h),
/// numbered as SegmentationPhase numbers them (docs/THEORY.md §6). A phase reads and changes the
/// state only: no phase calls another, and SegmentationKernel runs them in order.

#include "slipfit/segmentation/segmentation_state.h"

namespace slipfit::phases {

void estimateScale(SegmentationState& s);        // 1  scale.cpp
void growSlippageSeeds(SegmentationState& s);    // 2  seeding.cpp
void growFreeSeeds(SegmentationState& s);        // 3  seeding.cpp
void mergeRegions(SegmentationState& s);         // 4  merging.cpp
void reviseTypes(SegmentationState& s);          // 5  types.cpp
void recoverFillets(SegmentationState& s);       // 6  fillets.cpp
void refineBoundaries(SegmentationState& s);     // 7  boundaries.cpp
void joinCreases(SegmentationState& s);          // 8  boundaries.cpp
void recoverSmallFaces(SegmentationState& s);    // 9  small_faces.cpp
void absorbFragments(SegmentationState& s);      // 10 merging.cpp
void mergeSettledRegions(SegmentationState& s);  // 11 merging.cpp
void dropNonSurfaces(SegmentationState& s);      // 12 finalize.cpp
void joinOccludedPieces(SegmentationState& s);   // 13 merging.cpp
/// Ends the run: the result with its segments largest first, each refitted on all its members.
SegmentationResult finalize(SegmentationState& s);  // finalize.cpp

}  // namespace slipfit::phases
