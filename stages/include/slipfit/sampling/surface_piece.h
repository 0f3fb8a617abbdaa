#pragma once
/// \file A bounded piece of one primitive that a ray can hit exactly: the building block of the
/// scenes a simulated range sensor sees (sensor_scene.h, range_scanner.h).
///
/// - parallelogram / triangle: on a plane, the points corner + s·edge_u + t·edge_v with s, t in
///   [0, 1] (triangle: s + t ≤ 1);
/// - disk: on a plane, the ring of radii [lo, hi] around `corner`;
/// - cylinder: heights a·(x − point) in [lo, hi];
/// - cone: axial distances a·(x − apex) in [lo, hi] (lo ≥ 0: the nappe that opens along a);
/// - sphere: the cap (x − c)·edge_u ≥ lo · radius around the unit direction edge_u (lo = −1: the
///   whole sphere);
/// - torus: the whole torus.

#include "slipfit/fitting/primitives.h"

#include <Eigen/Core>

#include <optional>

namespace slipfit {

enum class PieceBounds { parallelogram, triangle, disk, cylinder, cone, sphere, torus };

struct SurfacePiece {
  Primitive surface;  ///< the unbounded primitive the piece lies on: its true primitive
  PieceBounds bounds = PieceBounds::parallelogram;
  Eigen::Vector3d corner = Eigen::Vector3d::Zero();  ///< parallelogram, triangle; disk: centre
  Eigen::Vector3d edge_u = Eigen::Vector3d::UnitX(), edge_v = Eigen::Vector3d::UnitY();
  double lo = 0.0, hi = 0.0;
  /// The index (in its scene) of an earlier piece of the same surface that this one continues —
  /// a gable over its end wall — or −1: pieces so joined are one true segment.
  int continues = -1;

  /// The centre and radius of a ball holding the piece (for culling rays).
  std::pair<Eigen::Vector3d, double> boundingBall() const;
};

/// Builders; each returns a piece whose surface and bounds agree.
SurfacePiece parallelogram(const Eigen::Vector3d& corner, const Eigen::Vector3d& edge_u,
                           const Eigen::Vector3d& edge_v);
SurfacePiece triangle(const Eigen::Vector3d& corner, const Eigen::Vector3d& edge_u,
                      const Eigen::Vector3d& edge_v);
/// A ring of radii [inner, outer] around \a center in the plane of normal \a normal.
SurfacePiece disk(const Eigen::Vector3d& center, const Eigen::Vector3d& normal, double inner,
                  double outer);
/// The side of the cylinder of \a radius around the unit axis through \a base, heights [0, h].
SurfacePiece cylinderSide(const Eigen::Vector3d& base, const Eigen::Vector3d& axis, double radius,
                          double height);
/// The band [from, to] of axial distances of the cone of apex \a apex, unit axis \a axis (into
/// the opening) and half angle \a half_angle (radians).
SurfacePiece coneBand(const Eigen::Vector3d& apex, const Eigen::Vector3d& axis, double half_angle,
                      double from, double to);
/// The cap of half angle acos(\a cos_cap) around the unit direction \a up (cos_cap = −1: the whole
/// sphere).
SurfacePiece sphereCap(const Eigen::Vector3d& center, double radius, const Eigen::Vector3d& up,
                       double cos_cap = -1.0);
SurfacePiece torus(const Eigen::Vector3d& center, const Eigen::Vector3d& axis, double major,
                   double minor);

/// The smallest t in (t_min, t_max) with origin + t·direction on the piece (direction a unit
/// vector), or nothing. Exact for the quadrics (roots of the quadratic); the torus by sphere
/// tracing its exact signed distance to 1e-9 of its size.
std::optional<double> intersect(const SurfacePiece& piece, const Eigen::Vector3d& origin,
                                const Eigen::Vector3d& direction, double t_min, double t_max);

}  // namespace slipfit
