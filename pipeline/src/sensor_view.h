#pragma once
/// \file When a PCD is a sensor's view: one rule for the reader (readCloud) and the streaming
/// reader of tiled runs (CloudStream).

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>

namespace slipfit::pipeline {

/// Whether a PCD of \a height rows with this VIEWPOINT (\a origin, \a orientation) is a sensor's
/// view: organized, or posed (a VIEWPOINT other than PCL's default, the identity at the origin),
/// with a finite pose and a non-zero quaternion.
inline bool isSensorView(const Eigen::Vector3d& origin, const Eigen::Quaterniond& orientation,
                         std::uint64_t height) {
  if (!origin.allFinite() || !orientation.coeffs().allFinite() || !(orientation.norm() > 0.0))
    return false;
  const bool posed = origin.squaredNorm() > 0.0 ||
                     !orientation.coeffs().isApprox(Eigen::Quaterniond::Identity().coeffs());
  return height > 1 || posed;
}

}  // namespace slipfit::pipeline
