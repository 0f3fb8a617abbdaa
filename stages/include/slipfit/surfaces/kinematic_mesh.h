#pragma once
/// \file A fitted kinematic surface (kinematic_surface.h) as a quad mesh for MeshLab: its profile
/// swept by its motion over the stretch of the motion that the points cover — the angles about
/// the axis a revolution's points span (all of them when no gap is wider than two steps), the
/// length of an extrusion along its direction, the heights along a helix's axis.

#include "slipfit/fitting/kinematic_surface.h"
#include "slipfit/surfaces/surface_mesh.h"

#include <Eigen/Core>

namespace slipfit {

/// The swept mesh of \a s over the stretch of its motion that 3 × N \a points (N ≥ 1) cover, in
/// \a steps (≥ 1) steps: (steps + 1) × V vertices for a profile of V vertices (steps × V for a
/// revolution all the way round), one quad per segment and step, vertex normals from the faces
/// (their side follows the profile's direction, not the outside). Throws std::invalid_argument
/// for an empty profile, no points or steps < 1.
SurfaceMesh kinematicMesh(const KinematicSurface& s,
                          const Eigen::Ref<const Eigen::Matrix3Xd>& points, int steps);

/// The parameter of \a p along the motion of \a s: the angle about the axis from the reference
/// (revolution, in (−π, π]), the position along the direction (extrusion), the screw angle
/// (helix: the height less the profile's unscrewed height, over the pitch; continuous over turns).
double motionParameter(const KinematicSurface& s, const Eigen::Vector3d& p);

/// The point of \a s at profile vertex \a v moved by the motion's parameter \a t
/// (motionParameter's inverse for points on the surface).
Eigen::Vector3d sweptPoint(const KinematicSurface& s, const Eigen::Vector2d& v, double t);

}  // namespace slipfit
