#include "slipfit/segmentation/segment_axis.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace slipfit {

std::optional<std::array<Eigen::Vector3d, 2>> axisStretch(
    const Segment& segment,
    const Eigen::Ref<const Eigen::Matrix3Xf, 0, Eigen::OuterStride<>>& points, double margin) {
  if (!segment.kinematic || segment.indices.empty())
    return std::nullopt;
  const KinematicSurface& s = segment.kinematic->surface;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const int i : segment.indices) {
    const double t = (points.col(i).cast<double>() - s.point).dot(s.axis);
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  if (!std::isfinite(lo) || !std::isfinite(hi))
    return std::nullopt;
  const double extra = margin * (hi - lo);
  return std::array<Eigen::Vector3d, 2>{s.point + (lo - extra) * s.axis,
                                        s.point + (hi + extra) * s.axis};
}

}  // namespace slipfit
