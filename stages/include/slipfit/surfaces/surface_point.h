#pragma once
/// \file The result of evaluating a parametric surface at (u, v).

#include <Eigen/Core>

namespace slipfit {

/// Position, first partial derivatives and unit normal Su × Sv / ‖Su × Sv‖ (zero when the
/// surface is singular there) of a surface at one parameter.
struct SurfacePoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d du = Eigen::Vector3d::Zero();
  Eigen::Vector3d dv = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
};

/// Completes a SurfacePoint from homogeneous [w; x; y; z] values H, Hu, Hv (w first):
/// S = X/w, Su = (Xu − wu S)/w. Throws DegenerateInputError when w is zero or not finite.
SurfacePoint dehomogenize(const Eigen::Vector4d& h, const Eigen::Vector4d& hu,
                          const Eigen::Vector4d& hv);

}  // namespace slipfit
