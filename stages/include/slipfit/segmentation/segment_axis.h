#pragma once
/// \file The axis of a kinematic segment where its points are: the stretch of the motion's axis
/// (the rotation, translation or screw axis) that their projections cover, for drawing it.

#include "slipfit/segmentation/segmentation.h"

#include <Eigen/Core>

#include <array>
#include <optional>

namespace slipfit {

/// The ends of the stretch of \a segment's axis that the projections of its points (columns of
/// \a points, by the segment's indices) cover, widened by \a margin of its length at each end;
/// empty for a segment without a kinematic surface, without points, or with non-finite ones.
std::optional<std::array<Eigen::Vector3d, 2>> axisStretch(
    const Segment& segment,
    const Eigen::Ref<const Eigen::Matrix3Xf, 0, Eigen::OuterStride<>>& points, double margin);

}  // namespace slipfit
