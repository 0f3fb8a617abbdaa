#include "slipfit/surfaces/rational_bezier_patch.h"

#include "slipfit/core/exceptions.h"

#include <array>
#include <cmath>
#include <string>

namespace slipfit {

SurfacePoint dehomogenize(const Eigen::Vector4d& h, const Eigen::Vector4d& hu,
                          const Eigen::Vector4d& hv) {
  const double w = h[0];
  if (w == 0.0 || !std::isfinite(w))
    throw DegenerateInputError("surface evaluation: the weight vanishes (a point at infinity)");
  SurfacePoint s;
  s.position = h.tail<3>() / w;
  s.du = (hu.tail<3>() - hu[0] * s.position) / w;
  s.dv = (hv.tail<3>() - hv[0] * s.position) / w;
  const Eigen::Vector3d c = s.du.cross(s.dv);
  const double norm = c.norm();
  if (norm > 0.0 && std::isfinite(norm))
    s.normal = c / norm;
  return s;
}

RationalBezierPatch::RationalBezierPatch(int degree_u, int degree_v,
                                         std::vector<HomogeneousPoint> sites)
    : m_(degree_u), n_(degree_v), sites_(std::move(sites)) {
  if (m_ < 0 || n_ < 0)
    throw InvalidParameterError("Bézier patch: degrees must be non-negative");
  const auto expected = static_cast<std::size_t>((m_ + 1) * (n_ + 1));
  if (sites_.size() != expected)
    throw InvalidParameterError("Bézier patch of degree (" + std::to_string(m_) + ", " +
                                std::to_string(n_) + ") needs " + std::to_string(expected) +
                                " sites, got " + std::to_string(sites_.size()));
  for (const auto& s : sites_)
    if (!s.allFinite())
      throw InvalidParameterError("Bézier patch: a site is not finite");
}

namespace {

/// de Casteljau scratch space: on the stack below degree 16, so evaluation does not allocate.
class Scratch {
 public:
  explicit Scratch(std::size_t n) : n_(n) {
    if (n > kStack)
      heap_.resize(n);
  }
  HomogeneousPoint& operator[](std::size_t i) { return n_ > kStack ? heap_[i] : stack_[i]; }
  std::size_t size() const { return n_; }

 private:
  static constexpr std::size_t kStack = 16;
  std::size_t n_;
  std::array<HomogeneousPoint, kStack> stack_;
  std::vector<HomogeneousPoint> heap_;
};

/// de Casteljau on \a points (in place) down to the last \a keep points.
void reduce(Scratch& points, double t, std::size_t keep) {
  for (std::size_t level = points.size(); level > keep; --level)
    for (std::size_t k = 0; k + 1 < level; ++k)
      points[k] = (1.0 - t) * points[k] + t * points[k + 1];
}

void checkParameter(double u, double v) {
  if (!(u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0))
    throw InvalidParameterError("Bézier patch: parameter (" + std::to_string(u) + ", " +
                                std::to_string(v) + ") outside [0, 1]²");
}

}  // namespace

HomogeneousPoint RationalBezierPatch::evaluateHomogeneous(double u, double v) const {
  checkParameter(u, v);
  Scratch column(static_cast<std::size_t>(m_ + 1)), row(static_cast<std::size_t>(n_ + 1));
  for (int i = 0; i <= m_; ++i) {
    for (int j = 0; j <= n_; ++j)
      row[j] = site(i, j);
    reduce(row, v, 1);
    column[i] = row[0];
  }
  reduce(column, u, 1);
  return column[0];
}

SurfacePoint RationalBezierPatch::evaluate(double u, double v) const {
  checkParameter(u, v);
  // Curves in u (one value per row, reduced in v) and in v (reduced in u); the last de Casteljau
  // level holds the value and the derivative: C(t) = (1−t) P0 + t P1, C'(t) = degree (P1 − P0).
  Scratch in_u(static_cast<std::size_t>(m_ + 1)), row(static_cast<std::size_t>(n_ + 1));
  for (int i = 0; i <= m_; ++i) {
    for (int j = 0; j <= n_; ++j)
      row[j] = site(i, j);
    reduce(row, v, 1);
    in_u[i] = row[0];
  }
  Scratch in_v(static_cast<std::size_t>(n_ + 1)), col(static_cast<std::size_t>(m_ + 1));
  for (int j = 0; j <= n_; ++j) {
    for (int i = 0; i <= m_; ++i)
      col[i] = site(i, j);
    reduce(col, u, 1);
    in_v[j] = col[0];
  }
  HomogeneousPoint h, hu = HomogeneousPoint::Zero(), hv = HomogeneousPoint::Zero();
  if (m_ > 0) {
    reduce(in_u, u, 2);
    h = (1.0 - u) * in_u[0] + u * in_u[1];
    hu = m_ * (in_u[1] - in_u[0]);
  } else {
    h = in_u[0];
  }
  if (n_ > 0) {
    reduce(in_v, v, 2);
    hv = n_ * (in_v[1] - in_v[0]);
  }
  return dehomogenize(h, hu, hv);
}

}  // namespace slipfit
