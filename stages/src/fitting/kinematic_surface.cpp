#include "slipfit/fitting/kinematic_surface.h"

#include "slipfit/core/angle_units.h"
#include "slipfit/core/name_table.h"

#include <cmath>
#include <limits>

namespace slipfit {

std::string_view kinematicTypeName(KinematicType type) {
  return nameIn(kKinematicTypeNames, type);
}

double KinematicSurface::period() const {
  return type == KinematicType::helix ? 2.0 * kPi * std::abs(pitch) : 0.0;
}

Eigen::Vector2d profileCoordinates(const KinematicSurface& s, const Eigen::Vector3d& p) {
  const Eigen::Vector3d w = p - s.point;
  const double h = w.dot(s.axis);
  const Eigen::Vector3d radial = w - h * s.axis;
  switch (s.type) {
    case KinematicType::revolution:
      return {h, radial.norm()};
    case KinematicType::extrusion:
      return {w.dot(s.reference), w.dot(s.axis.cross(s.reference))};
    case KinematicType::helix: {
      const double theta =
          std::atan2(radial.dot(s.axis.cross(s.reference)), radial.dot(s.reference));
      const double period = s.period();
      double unscrewed = h - s.pitch * theta;
      if (period > 0.0)
        unscrewed = s.cut + (unscrewed - s.cut) - period * std::floor((unscrewed - s.cut) / period);
      return {unscrewed, radial.norm()};
    }
  }
  return {h, radial.norm()};
}

namespace {

/// The helical metric's scale of the first profile coordinate at \a q (1 but for a helix): the
/// unscrewed height of a point moved by δ along a helicoid's normal at radius ρ changes by
/// δ √(ρ² + p²) / ρ, scaled back by ρ / √(ρ² + p²).
double firstScale(const KinematicSurface& s, const Eigen::Vector2d& q) {
  if (s.type != KinematicType::helix)
    return 1.0;
  const double rho = q.y();
  return rho / std::sqrt(rho * rho + s.pitch * s.pitch);
}

}  // namespace

ProfileProjection projectOnProfile(const KinematicSurface& s, const Eigen::Vector3d& p) {
  const Eigen::Vector2d q = profileCoordinates(s, p);
  return projectOnProfile(s.profile, q, firstScale(s, q), s.period());
}

KinematicProjector::KinematicProjector(const KinematicSurface& s)
    : surface_(&s), index_(s.profile, s.period()) {}

ProfileProjection KinematicProjector::project(const Eigen::Vector3d& p) const {
  const Eigen::Vector2d q = profileCoordinates(*surface_, p);
  return index_.project(q, firstScale(*surface_, q));
}

double distance(const Eigen::Vector3d& p, const KinematicSurface& s) {
  return projectOnProfile(s, p).distance;
}

int parameterCount(const KinematicSurface& s) {
  const int motion = s.type == KinematicType::revolution  ? 4
                     : s.type == KinematicType::extrusion ? 2
                                                          : 5;
  return motion + s.profile.parameterCount();
}

Eigen::Vector3d referenceAcross(const Eigen::Vector3d& axis) {
  const Eigen::Vector3d a = axis.normalized();
  const Eigen::Vector3d e = std::abs(a.x()) <= std::abs(a.y()) && std::abs(a.x()) <= std::abs(a.z())
                                ? Eigen::Vector3d::UnitX()
                            : std::abs(a.y()) <= std::abs(a.z()) ? Eigen::Vector3d::UnitY()
                                                                 : Eigen::Vector3d::UnitZ();
  return (e - e.dot(a) * a).normalized();
}

SectionFrame sectionFrame(const KinematicSurface& s) {
  SectionFrame f;
  f.e1 = (s.reference - s.reference.dot(s.axis) * s.axis).normalized();
  if (!f.e1.allFinite())
    f.e1 = referenceAcross(s.axis);
  f.e2 = s.axis.cross(f.e1);
  return f;
}

}  // namespace slipfit
