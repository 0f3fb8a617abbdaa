#pragma once
/// \file Two planes meeting at a crease, and a fillet of radius r rounding it: the cross-section
/// model SegmentationKernel::recoverFillets tests against the sharp crease (docs/THEORY.md §6
/// step 6c). A fillet whose radius is a few tens of σ lies mostly within the tolerance of the two
/// planes, which take its points as they grow; only the misfit of the middle rows, up to
/// r (1 − sin(opening / 2)) off both planes, tells it from an edge.

#include "slipfit/fitting/primitives.h"

#include <Eigen/Core>

#include <cstddef>
#include <optional>

namespace slipfit {

/// The crease of two planes, in the cross-section perpendicular to it.
struct CreaseSection {
  Eigen::Vector3d origin;  ///< a point of the crease line
  Eigen::Vector3d along;   ///< the crease's unit direction
  Eigen::Vector3d ua, ub;  ///< each plane's direction away from the crease, towards its points
  Eigen::Vector3d na, nb;  ///< the planes' unit normals
  double opening = 0.0;    ///< the angle between ua and ub (π: the planes are one), radians
};

/// The crease of \a a and \a b, whose points are \a points_a and \a points_b; nullopt when the
/// planes are parallel or cross (a plane's points lie on both sides of the crease line: at most
/// 5 % on the far side).
std::optional<CreaseSection> creaseSection(const Plane& a, const Plane& b,
                                           const Eigen::Ref<const Eigen::Matrix3Xd>& points_a,
                                           const Eigen::Ref<const Eigen::Matrix3Xd>& points_b);

/// Which piece of the rounded crease is nearest a point.
enum class FilletPiece { plane_a, plane_b, arc };

/// Distance from \a p to the crease rounded with \a radius (0: the sharp crease): the two planes
/// beyond their tangent points and the arc between them. Returns the nearest piece.
FilletPiece filletDistance(const CreaseSection& s, double radius, const Eigen::Vector3d& p,
                           double* distance);

struct FilletChoice {
  double radius = 0.0;      ///< 0: the sharp crease fits best
  double cost = 0.0;        ///< Σ min((d / σ)², 36) at the radius
  double sharp_cost = 0.0;  ///< the same for the sharp crease
  std::size_t on_arc = 0;   ///< points whose nearest piece is the arc
};

/// The radius in [smallest, largest] (or 0) that minimises Σ min((dᵢ / σᵢ)², 36) over the points
/// \a p with noise \a sigma: a geometric grid of 48 radii, then a golden-section search between
/// the best one's neighbours.
FilletChoice chooseFilletRadius(const CreaseSection& s, const Eigen::Ref<const Eigen::Matrix3Xd>& p,
                                const Eigen::Ref<const Eigen::VectorXd>& sigma, double smallest,
                                double largest);

}  // namespace slipfit
