#pragma once
/// \file The five primitive types, their parameters (one convention everywhere: code, YAML report,
/// docs) and exact point-to-surface distances.
///
/// - plane: unit normal n and d with n·x = d.
/// - sphere: centre c, radius r.
/// - cylinder: unit axis a, a point c on the axis (the foot of the perpendicular from the weighted
///   centroid of the fitted points), radius r.
/// - cone: unit axis a pointing from the apex into the opening, apex c, half angle θ ∈ (0, π/2).
/// - torus: unit axis a, centre c (on the axis, in the plane of the circle of tube centres), major
///   radius R > 0 (the circle of tube centres), minor radius r > 0 (the tube). The surface is
///   (ρ − R)² + z² = r² with z = a·(x − c) and ρ the distance of x from the axis; r ≥ R (a
///   spindle torus) is allowed for fits, and the signed distance stays exact on its outer part.

#include <Eigen/Core>

#include <array>
#include <string_view>
#include <variant>

namespace slipfit {

enum class PrimitiveType { plane, sphere, cylinder, cone, torus };
constexpr std::array<std::pair<PrimitiveType, std::string_view>, 5> kPrimitiveTypeNames{{
    {PrimitiveType::plane, "plane"},
    {PrimitiveType::sphere, "sphere"},
    {PrimitiveType::cylinder, "cylinder"},
    {PrimitiveType::cone, "cone"},
    {PrimitiveType::torus, "torus"},
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

struct Torus {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double major_radius = 1.0;   ///< R, the radius of the circle of tube centres
  double minor_radius = 0.25;  ///< r, the tube's radius
};

/// The variant's index is the PrimitiveType (and the PLY `primitive` code): 0 … 4.
using Primitive = std::variant<Plane, Sphere, Cylinder, Cone, Torus>;
PrimitiveType typeOf(const Primitive& primitive);

/// Every parameter is finite (no NaN or inf): the check every fit and report makes.
bool allFinite(const Primitive& primitive);

/// Signed distance: positive outside (plane: on the normal's side; sphere, cylinder: away from the
/// centre/axis; cone: away from the axis; torus: away from the circle of tube centres). For the
/// cone, points whose nearest surface point is the apex get +‖p − c‖.
double signedDistance(const Eigen::Vector3d& p, const Plane& s);
double signedDistance(const Eigen::Vector3d& p, const Sphere& s);
double signedDistance(const Eigen::Vector3d& p, const Cylinder& s);
double signedDistance(const Eigen::Vector3d& p, const Cone& s);
double signedDistance(const Eigen::Vector3d& p, const Torus& s);
double signedDistance(const Eigen::Vector3d& p, const Primitive& s);

/// Exact Euclidean distance D(p, A) = |signedDistance|.
inline double distance(const Eigen::Vector3d& p, const Primitive& s) {
  return std::abs(signedDistance(p, s));
}

/// Outward unit normal of the surface at the point nearest to \a p (the gradient of the signed
/// distance). Where it is undefined (p on the axis or at the centre, p on the torus's circle of
/// tube centres) some unit vector ⟂ the axis.
Eigen::Vector3d surfaceNormal(const Eigen::Vector3d& p, const Primitive& s);

/// The signed distance of every column of \a points (3 × N) to \a primitive, in \a out (N):
/// the shape's constants (a cone's cosine and sine) computed once.
void signedDistances(const Eigen::Ref<const Eigen::Matrix3Xd>& points, const Primitive& primitive,
                     Eigen::Ref<Eigen::VectorXd> out);

/// Σ wᵢ D²(pᵢ, A) over the columns of \a points (3 × N) with weights \a weights (N).
double weightedLoss(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                    const Eigen::Ref<const Eigen::VectorXd>& weights, const Primitive& primitive);

}  // namespace slipfit
