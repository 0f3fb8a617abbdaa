#pragma once
/// \file Kinematic surfaces as fitted models: a surface that one rigid motion slides into itself,
/// given by that motion and a profile curve (profile_curve.h).
///  - revolution: the rotation about an axis; the profile is the meridian, (h, ρ) = (height along
///    the axis, distance from it);
///  - extrusion: the translation along a direction; the profile is the cross-section, (x, y) in
///    the plane across the direction;
///  - helix: the screw about an axis with a pitch (rise per radian); the profile is the section
///    unscrewed to θ = 0, (h − pitch θ, ρ), on a strip 2π |pitch| wide that repeats.
/// The distance of a point is its profile-plane distance to the profile: exact for revolutions and
/// extrusions (the nearest surface point lies in the point's own meridian or section); for the
/// helix, the unscrewed height is scaled by ρ / √(ρ² + pitch²), which makes it exact for a
/// displacement along the surface normal of a helicoid and across a profile parallel to the axis,
/// and first-order in between (docs/THEORY.md §5.5). Pure Eigen.

#include "slipfit/fitting/profile_curve.h"

#include <Eigen/Core>

#include <array>
#include <string>
#include <string_view>
#include <utility>

namespace slipfit {

enum class KinematicType { revolution, extrusion, helix };
constexpr std::array<std::pair<KinematicType, std::string_view>, 3> kKinematicTypeNames{{
    {KinematicType::revolution, "revolution"},
    {KinematicType::extrusion, "extrusion"},
    {KinematicType::helix, "helix"},
}};
std::string_view kinematicTypeName(KinematicType type);

struct KinematicSurface {
  KinematicType type = KinematicType::revolution;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  ///< unit: rotation, translation or screw axis
  /// On the axis: the origin of the heights (revolution, helix) and of the section (extrusion).
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  /// Unit, across the axis: the section's x (extrusion), θ = 0 (helix); unused for revolutions.
  Eigen::Vector3d reference = Eigen::Vector3d::UnitX();
  double pitch = 0.0;  ///< helix: rise per radian along the axis (signed, ≠ 0)
  /// helix: the unscrewed heights are taken in [cut, cut + 2π |pitch|)
  double cut = 0.0;
  ProfileCurve profile;  ///< in the profile plane above, units

  /// The width of the helix's strip, 2π |pitch|; 0 for the others.
  double period() const;
};

/// \a p's coordinates in the profile plane of \a s (see the file comment).
Eigen::Vector2d profileCoordinates(const KinematicSurface& s, const Eigen::Vector3d& p);

/// Where \a p meets the profile in its profile plane, in the surface's metric (the helical one
/// for a helix): profile_curve.h's projection of profileCoordinates(s, p).
ProfileProjection projectOnProfile(const KinematicSurface& s, const Eigen::Vector3d& p);

/// Distance from \a p to the surface (see the file comment); infinity for an empty profile.
double distance(const Eigen::Vector3d& p, const KinematicSurface& s);

/// projectOnProfile(s, p) and distance(p, s) for many points on one surface, through a
/// ProfileIndex of its profile: the same values. Keeps a pointer to \a s, which must outlive it
/// unchanged.
class KinematicProjector {
 public:
  explicit KinematicProjector(const KinematicSurface& s);
  ProfileProjection project(const Eigen::Vector3d& p) const;
  double distance(const Eigen::Vector3d& p) const { return project(p).distance; }

 private:
  const KinematicSurface* surface_;
  ProfileIndex index_;
};

/// Free parameters: the motion's (revolution 4: the axis direction and its foot; extrusion 2: the
/// direction, the section's placement being the profile's; helix 5: those of the revolution and
/// the pitch) plus the profile's 2 per vertex.
int parameterCount(const KinematicSurface& s);

/// A unit vector across \a axis chosen continuously from it (the x of its section frame).
Eigen::Vector3d referenceAcross(const Eigen::Vector3d& axis);

/// The right-handed frame across the axis of \a s: e1 the reference made perpendicular to the
/// axis (referenceAcross when it is along it), e2 = axis × e1.
struct SectionFrame {
  Eigen::Vector3d e1, e2;
};
SectionFrame sectionFrame(const KinematicSurface& s);

}  // namespace slipfit
