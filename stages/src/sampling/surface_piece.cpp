#include "slipfit/sampling/surface_piece.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>

namespace slipfit {

namespace {

/// The roots of a t² + b t + c = 0 in ascending order (none, one for a ≈ 0, or two); b is
/// halved in the formula (b = 2 h) and the root of smaller magnitude is taken from the product of
/// the roots, which keeps both accurate.
int quadraticRoots(double a, double b, double c, std::array<double, 2>& t) {
  const double h = 0.5 * b;
  if (std::abs(a) < 1e-14 * (std::abs(h) + std::abs(c))) {
    if (h == 0.0)
      return 0;
    t[0] = -c / b;
    return 1;
  }
  const double disc = h * h - a * c;
  if (disc < 0.0)
    return 0;
  const double q = -(h + std::copysign(std::sqrt(disc), h));
  t[0] = q / a;
  t[1] = q != 0.0 ? c / q : t[0];
  if (t[0] > t[1])
    std::swap(t[0], t[1]);
  return 2;
}

/// The point at \a t lies within the piece's bounds (its surface is already hit).
bool withinBounds(const SurfacePiece& p, const Eigen::Vector3d& x) {
  switch (p.bounds) {
    case PieceBounds::parallelogram:
    case PieceBounds::triangle: {
      // (s, t) from the 2 × 2 normal equations of x − corner = s·u + t·v.
      const Eigen::Vector3d w = x - p.corner;
      const double uu = p.edge_u.squaredNorm(), uv = p.edge_u.dot(p.edge_v),
                   vv = p.edge_v.squaredNorm(), wu = w.dot(p.edge_u), wv = w.dot(p.edge_v);
      const double det = uu * vv - uv * uv;
      const double s = (wu * vv - wv * uv) / det, t = (wv * uu - wu * uv) / det;
      if (s < 0.0 || t < 0.0)
        return false;
      return p.bounds == PieceBounds::triangle ? s + t <= 1.0 : s <= 1.0 && t <= 1.0;
    }
    case PieceBounds::disk: {
      const double r = (x - p.corner).norm();
      return r >= p.lo && r <= p.hi;
    }
    case PieceBounds::cylinder: {
      const auto& c = std::get<Cylinder>(p.surface);
      const double h = c.axis.dot(x - c.point);
      return h >= p.lo && h <= p.hi;
    }
    case PieceBounds::cone: {
      const auto& c = std::get<Cone>(p.surface);
      const double h = c.axis.dot(x - c.apex);
      return h >= p.lo && h <= p.hi;
    }
    case PieceBounds::sphere: {
      const auto& s = std::get<Sphere>(p.surface);
      return (x - s.center).dot(p.edge_u) >= p.lo * s.radius;
    }
    case PieceBounds::torus:
      return true;
  }
  return false;
}

/// The roots of the unbounded quadric along the ray, ascending; 0, 1 or 2 of them.
int quadricRoots(const Primitive& surface, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                 std::array<double, 2>& t) {
  if (const auto* pl = std::get_if<Plane>(&surface)) {
    const double nd = pl->normal.dot(d);
    if (nd == 0.0)
      return 0;
    t[0] = (pl->d - pl->normal.dot(o)) / nd;
    return 1;
  }
  if (const auto* s = std::get_if<Sphere>(&surface)) {
    const Eigen::Vector3d w = o - s->center;
    return quadraticRoots(1.0, 2.0 * w.dot(d), w.squaredNorm() - s->radius * s->radius, t);
  }
  if (const auto* c = std::get_if<Cylinder>(&surface)) {
    // |w⊥|² = r² with w⊥ the part of o + t d − point perpendicular to the axis.
    const Eigen::Vector3d w = o - c->point;
    const Eigen::Vector3d dp = d - d.dot(c->axis) * c->axis, wp = w - w.dot(c->axis) * c->axis;
    return quadraticRoots(dp.squaredNorm(), 2.0 * dp.dot(wp),
                          wp.squaredNorm() - c->radius * c->radius, t);
  }
  const auto& k = std::get<Cone>(surface);
  // (w·a)² = cos²θ |w|², w = o + t d − apex (both nappes; the bounds keep the opening one).
  const Eigen::Vector3d w = o - k.apex;
  const double c2 = std::pow(std::cos(k.half_angle), 2);
  const double da = d.dot(k.axis), wa = w.dot(k.axis);
  return quadraticRoots(da * da - c2, 2.0 * (da * wa - c2 * d.dot(w)),
                        wa * wa - c2 * w.squaredNorm(), t);
}

/// The first root of the torus's signed distance along the ray in (t_min, t_max): sphere
/// tracing, which cannot step over the surface because the signed distance is exact (1-Lipschitz).
std::optional<double> traceTorus(const Torus& torus, const Eigen::Vector3d& o,
                                 const Eigen::Vector3d& d, double t_min, double t_max) {
  const double eps = 1e-9 * (torus.major_radius + torus.minor_radius);
  double t = t_min;
  for (int i = 0; i < 10000 && t < t_max; ++i) {
    const double f = signedDistance(Eigen::Vector3d(o + t * d), torus);
    if (f < eps)
      return f > -eps || i > 0 ? std::optional<double>(t) : std::nullopt;
    t += f;
  }
  return std::nullopt;
}

}  // namespace

std::pair<Eigen::Vector3d, double> SurfacePiece::boundingBall() const {
  switch (bounds) {
    case PieceBounds::parallelogram:
    case PieceBounds::triangle: {
      const Eigen::Vector3d c = corner + 0.5 * (edge_u + edge_v);
      const double r =
          std::max({(corner - c).norm(), (corner + edge_u - c).norm(), (corner + edge_v - c).norm(),
                    (corner + edge_u + edge_v - c).norm()});
      return {c, r};
    }
    case PieceBounds::disk:
      return {corner, hi};
    case PieceBounds::cylinder: {
      const auto& c = std::get<Cylinder>(surface);
      return {c.point + 0.5 * (lo + hi) * c.axis, std::hypot(0.5 * (hi - lo), c.radius)};
    }
    case PieceBounds::cone: {
      const auto& c = std::get<Cone>(surface);
      return {c.apex + 0.5 * (lo + hi) * c.axis,
              std::hypot(0.5 * (hi - lo), hi * std::tan(c.half_angle))};
    }
    case PieceBounds::sphere: {
      const auto& s = std::get<Sphere>(surface);
      return {s.center, s.radius};
    }
    case PieceBounds::torus: {
      const auto& t = std::get<Torus>(surface);
      return {t.center, t.major_radius + t.minor_radius};
    }
  }
  return {corner, 0.0};
}

SurfacePiece parallelogram(const Eigen::Vector3d& corner, const Eigen::Vector3d& edge_u,
                           const Eigen::Vector3d& edge_v) {
  const Eigen::Vector3d n = edge_u.cross(edge_v).normalized();
  SurfacePiece p;
  p.surface = Plane{n, n.dot(corner)};
  p.bounds = PieceBounds::parallelogram;
  p.corner = corner;
  p.edge_u = edge_u;
  p.edge_v = edge_v;
  return p;
}

SurfacePiece triangle(const Eigen::Vector3d& corner, const Eigen::Vector3d& edge_u,
                      const Eigen::Vector3d& edge_v) {
  SurfacePiece p = parallelogram(corner, edge_u, edge_v);
  p.bounds = PieceBounds::triangle;
  return p;
}

SurfacePiece disk(const Eigen::Vector3d& center, const Eigen::Vector3d& normal, double inner,
                  double outer) {
  const Eigen::Vector3d n = normal.normalized();
  SurfacePiece p;
  p.surface = Plane{n, n.dot(center)};
  p.bounds = PieceBounds::disk;
  p.corner = center;
  p.lo = inner;
  p.hi = outer;
  return p;
}

SurfacePiece cylinderSide(const Eigen::Vector3d& base, const Eigen::Vector3d& axis, double radius,
                          double height) {
  SurfacePiece p;
  p.surface = Cylinder{axis.normalized(), base, radius};
  p.bounds = PieceBounds::cylinder;
  p.lo = 0.0;
  p.hi = height;
  return p;
}

SurfacePiece coneBand(const Eigen::Vector3d& apex, const Eigen::Vector3d& axis, double half_angle,
                      double from, double to) {
  SurfacePiece p;
  p.surface = Cone{axis.normalized(), apex, half_angle};
  p.bounds = PieceBounds::cone;
  p.lo = from;
  p.hi = to;
  return p;
}

SurfacePiece sphereCap(const Eigen::Vector3d& center, double radius, const Eigen::Vector3d& up,
                       double cos_cap) {
  SurfacePiece p;
  p.surface = Sphere{center, radius};
  p.bounds = PieceBounds::sphere;
  p.edge_u = up.normalized();
  p.lo = cos_cap;
  return p;
}

SurfacePiece torus(const Eigen::Vector3d& center, const Eigen::Vector3d& axis, double major,
                   double minor) {
  SurfacePiece p;
  p.surface = Torus{axis.normalized(), center, major, minor};
  p.bounds = PieceBounds::torus;
  return p;
}

std::optional<double> intersect(const SurfacePiece& piece, const Eigen::Vector3d& origin,
                                const Eigen::Vector3d& direction, double t_min, double t_max) {
  // Cull by the bounding ball: the ray's interval inside it, if any.
  const auto [centre, radius] = piece.boundingBall();
  const Eigen::Vector3d w = origin - centre;
  const double b = w.dot(direction), c = w.squaredNorm() - radius * radius;
  const double disc = b * b - c;
  if (disc < 0.0)
    return std::nullopt;
  const double root = std::sqrt(disc);
  const double enter = std::max(t_min, -b - root), leave = std::min(t_max, -b + root);
  if (enter > leave)
    return std::nullopt;
  if (const auto* t = std::get_if<Torus>(&piece.surface))
    return traceTorus(*t, origin, direction, std::max(enter, t_min), leave);
  std::array<double, 2> roots{};
  const int n = quadricRoots(piece.surface, origin, direction, roots);
  for (int i = 0; i < n; ++i) {
    const double t = roots[static_cast<std::size_t>(i)];
    if (t > t_min && t < t_max && withinBounds(piece, origin + t * direction))
      return t;
  }
  return std::nullopt;
}

}  // namespace slipfit
