#include "slipfit/fitting/primitives.h"
#include "slipfit/core/name_table.h"

#include <Eigen/Geometry>

#include <cmath>
#include <type_traits>

namespace slipfit {

std::string_view primitiveTypeName(PrimitiveType type) {
  return nameIn(kPrimitiveTypeNames, type);
}

PrimitiveType typeOf(const Primitive& primitive) {
  return static_cast<PrimitiveType>(primitive.index());
}

bool allFinite(const Primitive& primitive) {
  return std::visit(
      [](const auto& s) {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, Plane>)
          return s.normal.allFinite() && std::isfinite(s.d);
        else if constexpr (std::is_same_v<T, Sphere>)
          return s.center.allFinite() && std::isfinite(s.radius);
        else if constexpr (std::is_same_v<T, Cylinder>)
          return s.axis.allFinite() && s.point.allFinite() && std::isfinite(s.radius);
        else if constexpr (std::is_same_v<T, Cone>)
          return s.axis.allFinite() && s.apex.allFinite() && std::isfinite(s.half_angle);
        else
          return s.axis.allFinite() && s.center.allFinite() && std::isfinite(s.major_radius) &&
                 std::isfinite(s.minor_radius);
      },
      primitive);
}

double signedDistance(const Eigen::Vector3d& p, const Plane& s) {
  return s.normal.dot(p) - s.d;
}

double signedDistance(const Eigen::Vector3d& p, const Sphere& s) {
  return (p - s.center).norm() - s.radius;
}

double signedDistance(const Eigen::Vector3d& p, const Cylinder& s) {
  const Eigen::Vector3d v = p - s.point;
  return (v - v.dot(s.axis) * s.axis).norm() - s.radius;
}

namespace {

/// A cone with its half angle's cosine and sine, computed once for many points.
struct ConeFrame {
  const Cone& cone;
  double c, sn;
  explicit ConeFrame(const Cone& s)
      : cone(s), c(std::cos(s.half_angle)), sn(std::sin(s.half_angle)) {}
  double operator()(const Eigen::Vector3d& p) const {
    // In the half-plane through the axis and p: h along the axis, ρ ≥ 0 away from it. The cone
    // is the ray from the apex at angle θ to the axis, direction (cos θ, sin θ).
    const Eigen::Vector3d v = p - cone.apex;
    const double h = v.dot(cone.axis);
    const double rho = (v - h * cone.axis).norm();
    if (h * c + rho * sn < 0.0)
      return v.norm();  // beyond 90° from the ray: the apex is nearest
    return rho * c - h * sn;
  }
};

/// The signed distance to \a shape as a function of the point, its constants computed once.
template <typename Shape>
auto distanceTo(const Shape& shape) {
  if constexpr (std::is_same_v<Shape, Cone>)
    return ConeFrame(shape);
  else
    return [&shape](const Eigen::Vector3d& p) { return signedDistance(p, shape); };
}

}  // namespace

double signedDistance(const Eigen::Vector3d& p, const Cone& s) {
  return ConeFrame(s)(p);
}

double signedDistance(const Eigen::Vector3d& p, const Torus& s) {
  // In the half-plane through the axis and p: (ρ, z); the tube's cross-section is the circle of
  // radius r about (R, 0), and the nearest point of the circle is along the ray from its centre.
  const Eigen::Vector3d v = p - s.center;
  const double z = v.dot(s.axis);
  const double rho = (v - z * s.axis).norm();
  // sqrt, not std::hypot (several times slower, and the distances are of unit order in the
  // fits' normalised coordinates: no overflow to guard against).
  const double a = rho - s.major_radius;
  return std::sqrt(a * a + z * z) - s.minor_radius;
}

double signedDistance(const Eigen::Vector3d& p, const Primitive& s) {
  return std::visit([&](const auto& shape) { return signedDistance(p, shape); }, s);
}

namespace {

/// Unit radial direction of \a v away from \a axis (any ⟂ direction on the axis).
Eigen::Vector3d radial(const Eigen::Vector3d& v, const Eigen::Vector3d& axis) {
  const Eigen::Vector3d r = v - v.dot(axis) * axis;
  const double n = r.norm();
  return n > 0.0 ? Eigen::Vector3d(r / n) : Eigen::Vector3d(axis.unitOrthogonal());
}

}  // namespace

Eigen::Vector3d surfaceNormal(const Eigen::Vector3d& p, const Primitive& s) {
  if (const auto* plane = std::get_if<Plane>(&s))
    return plane->normal;
  if (const auto* sphere = std::get_if<Sphere>(&s)) {
    const Eigen::Vector3d v = p - sphere->center;
    const double n = v.norm();
    return n > 0.0 ? Eigen::Vector3d(v / n) : Eigen::Vector3d::UnitZ();
  }
  if (const auto* cylinder = std::get_if<Cylinder>(&s))
    return radial(p - cylinder->point, cylinder->axis);
  if (const auto* torus = std::get_if<Torus>(&s)) {
    // From the nearest tube centre (on the circle of radius R) towards p.
    const Eigen::Vector3d v = p - torus->center;
    const Eigen::Vector3d tube = torus->major_radius * radial(v, torus->axis);
    const Eigen::Vector3d d = v - tube;
    const double n = d.norm();
    return n > 0.0 ? Eigen::Vector3d(d / n) : radial(v, torus->axis);
  }
  const auto& cone = std::get<Cone>(s);
  const Eigen::Vector3d v = p - cone.apex;
  // In the half-plane through the axis: the generator is (cos θ, sin θ) in (axis, radial), its
  // outward normal (−sin θ, cos θ).
  return std::cos(cone.half_angle) * radial(v, cone.axis) - std::sin(cone.half_angle) * cone.axis;
}

void signedDistances(const Eigen::Ref<const Eigen::Matrix3Xd>& points, const Primitive& primitive,
                     Eigen::Ref<Eigen::VectorXd> out) {
  std::visit(
      [&](const auto& shape) {
        const auto to = distanceTo(shape);
        for (Eigen::Index i = 0; i < points.cols(); ++i)
          out[i] = to(points.col(i));
      },
      primitive);
}

double weightedLoss(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                    const Eigen::Ref<const Eigen::VectorXd>& weights, const Primitive& primitive) {
  return std::visit(
      [&](const auto& shape) {
        const auto to = distanceTo(shape);
        double loss = 0.0;
        for (Eigen::Index i = 0; i < points.cols(); ++i) {
          if (!(weights[i] > 0.0))
            continue;  // zero weight: no influence, even when not finite
          const double d = to(points.col(i));
          loss += weights[i] * d * d;
        }
        return loss;
      },
      primitive);
}

}  // namespace slipfit
