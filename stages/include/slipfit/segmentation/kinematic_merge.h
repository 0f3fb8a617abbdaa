#pragma once
/// \file Segmentation into kinematic surfaces (issue 37): after the primitive segmentation, groups
/// of adjacent segments whose primitives share a motion — one axis line (cylinders, cones, tori,
/// spheres centred on it: a turned part or a thread in pieces) or one direction (cylinders with
/// parallel axes: an extruded section in strips) — are classified as one
/// cloud (shape_classification.h). A group becomes one kinematic segment when a surface of
/// revolution, an extrusion or a helix with its fitted profile explains its points and beats the
/// primitives by BIC; otherwise its segments stay as they are: the simplest adequate model first.
/// A plane joins a group only along its axis and when no larger than four times its curved points
/// (a plate and the turned part on it are one surface of revolution, and the plate is a plane);
/// a member that a plane across the axis explains (a flat top) is put back. The kinematic segment
/// then takes the adjacent segments its surface explains as well as their own primitives do,
/// the pieces on its axis whose union with it is again of its class, and the unassigned points
/// next to it that it explains within the segmentation's tolerance. docs/THEORY.md §5.5.

#include "slipfit/neighborhoods/neighborhoods.h"
#include "slipfit/segmentation/segmentation.h"

#include <Eigen/Core>

#include <cstddef>

namespace slipfit {

/// Merges \a result's segments into kinematic segments where a kinematic surface explains a group
/// of them (see the file comment), over the 3 × N \a points and \a normals and the \a
/// neighborhoods the segmentation ran on; labels are renumbered largest first. Returns the
/// number of kinematic segments made. Deterministic.
std::size_t mergeKinematicSurfaces(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                   const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                                   const Neighborhoods& neighborhoods, SegmentationResult& result);

}  // namespace slipfit
