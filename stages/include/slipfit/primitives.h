#pragma once
/// \file The four primitive types, their parameters (one convention everywhere: code, YAML report,
/// docs) and exact point-to-surface distances.
///
/// - plane: unit normal n and d with n·x = d.
/// - sphere: centre c, radius r.
/// - cylinder: unit axis a, a point c on the axis (the foot of the perpendicular from the weighted
///   centroid of the fitted points), radius r.
/// - cone: unit axis a pointing from the apex into the opening, apex c, half angle θ ∈ (0, π/2).

#include <Eigen/Core>

#include <array>
#include <string_view>
#include <variant>

namespace slipfit {

enum class PrimitiveType { plane, sphere, cylinder, cone };
constexpr std::array<std::pair<PrimitiveType, std::string_view>, 4> kPrimitiveTypeNames{{
    {PrimitiveType::plane, "plane"},
    {PrimitiveType::sphere, "sphere"},
    {PrimitiveType::cylinder, "cylinder"},
    {PrimitiveType::cone, "cone"},
}};
std::string_view primitiveTypeName(PrimitiveType type);

struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double d = 0.0;
};
struct Sphere {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius = 1.0;
};
struct Cylinder {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double radius = 1.0;
};
struct Cone {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d apex = Eigen::Vector3d::Zero();
  double half_angle = 0.5;  ///< radians
};

using Primitive = std::variant<Plane, Sphere, Cylinder, Cone>;
PrimitiveType typeOf(const Primitive& primitive);

/// Signed distance: positive outside (plane: on the normal's side; sphere, cylinder: away from the
/// centre/axis; cone: away from the axis). For the cone, points whose nearest surface point is
/// the apex get +‖p − c‖.
double signedDistance(const Eigen::Vector3d& p, const Plane& s);
double signedDistance(const Eigen::Vector3d& p, const Sphere& s);
double signedDistance(const Eigen::Vector3d& p, const Cylinder& s);
double signedDistance(const Eigen::Vector3d& p, const Cone& s);
double signedDistance(const Eigen::Vector3d& p, const Primitive& s);

/// Exact Euclidean distance D(p, A) = |signedDistance|.
inline double distance(const Eigen::Vector3d& p, const Primitive& s) {
  return std::abs(signedDistance(p, s));
}

/// Outward unit normal of the surface at the point nearest to \a p (the gradient of the signed
/// distance). Where it is undefined (p on the axis or at the centre) some unit vector ⟂ the axis.
Eigen::Vector3d surfaceNormal(const Eigen::Vector3d& p, const Primitive& s);

/// Σ wᵢ D²(pᵢ, A) over the columns of \a points (3 × N) with weights \a weights (N).
double weightedLoss(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                    const Eigen::Ref<const Eigen::VectorXd>& weights, const Primitive& primitive);

}  // namespace slipfit
