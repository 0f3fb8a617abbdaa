#pragma once
/// \file Area-uniform samples of a kinematic surface (kinematic_surface.h) over a stretch of its
/// motion, with the exact unit normals of its polyline profile: the ground truth of generated
/// turned parts, extrusions and threads is the surface itself, and distance(p, s) of a sample
/// is 0 to rounding.

#include "slipfit/fitting/kinematic_surface.h"

#include <Eigen/Core>

#include <random>

namespace slipfit {

/// Where the motion takes the profile: the angles [from, to] about the axis from the reference
/// (revolution), the positions [from, to] along the direction (extrusion), the heights [from, to]
/// along the axis that each profile point sweeps (helix: vertex (u, ρ) turns through the screw
/// angles [(from − u) / pitch, (to − u) / pitch]).
struct MotionStretch {
  double from = 0.0, to = 0.0;
};

/// \a n samples of \a s over \a stretch, uniform in area (for a helix, to the trapezoidal rule
/// of kinematicArea on each segment), in 3 × n \a points and \a normals. The normals are those of
/// the polyline's surface, outward for a profile of rising height (revolution, helix) and for a
/// counter-clockwise section (extrusion). Throws std::invalid_argument for a profile of fewer
/// than 2 vertices, an empty stretch or a helix of zero pitch.
void sampleKinematicSurface(const KinematicSurface& s, const MotionStretch& stretch, std::size_t n,
                            std::mt19937_64& rng, Eigen::Matrix3Xd& points,
                            Eigen::Matrix3Xd& normals);

/// The area of \a s over \a stretch (exact for its polyline profile; for a helix, the integral of
/// √(ρ² + ρ'² pitch²) over the profile's arc, by the trapezoidal rule on each segment).
double kinematicArea(const KinematicSurface& s, const MotionStretch& stretch);

}  // namespace slipfit
