#include "slipfit/fitting/model_selection.h"

#include <cmath>
#include <limits>

namespace slipfit {

namespace {

/// RMS distance of the points from their centroid, in the plane across \a axis (all three
/// directions when \a axis is zero).
double spread(const Eigen::Ref<const Eigen::Matrix3Xd>& points, const Eigen::Vector3d& axis) {
  if (points.cols() == 0)
    return 0.0;
  const Eigen::Vector3d c = points.rowwise().mean();
  double sum = 0.0;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    const Eigen::Vector3d d = points.col(i) - c;
    sum += d.squaredNorm() - std::pow(d.dot(axis), 2);
  }
  return std::sqrt(sum / static_cast<double>(points.cols()));
}

}  // namespace

bool isNearlyDegenerate(const Primitive& primitive,
                        const Eigen::Ref<const Eigen::Matrix3Xd>& points) {
  if (const auto* s = std::get_if<Sphere>(&primitive))
    return s->radius > kFlatRadiusRatio * spread(points, Eigen::Vector3d::Zero());
  if (const auto* c = std::get_if<Cylinder>(&primitive))
    return c->radius > kFlatRadiusRatio * spread(points, c->axis.normalized());
  if (const auto* k = std::get_if<Cone>(&primitive)) {
    // Its curvature radius at the points: their (RMS) distance from the axis / cos(half-angle).
    // Near 0°, the apex far beyond the points: their RMS distance from it.
    const Eigen::Vector3d a = k->axis.normalized();
    double sum = 0.0, apex = 0.0;
    for (Eigen::Index i = 0; i < points.cols(); ++i) {
      const Eigen::Vector3d d = points.col(i) - k->apex;
      sum += (d - d.dot(a) * a).squaredNorm();
      apex += d.squaredNorm();
    }
    const double count = static_cast<double>(std::max<Eigen::Index>(1, points.cols()));
    const double rho = std::sqrt(sum / count);
    const double limit = kFlatRadiusRatio * spread(points, Eigen::Vector3d::Zero());
    return rho > limit * std::cos(k->half_angle) || std::sqrt(apex / count) > limit;
  }
  if (const auto* t = std::get_if<Torus>(&primitive))
    return std::max(t->major_radius, t->minor_radius) >
           kFlatRadiusRatio * spread(points, Eigen::Vector3d::Zero());
  return false;
}

bool jointModelIsBetter(double rss_joint, double rss_separate, std::size_t n,
                        int saved_parameters) {
  if (!(rss_separate > 0.0) || n < 2)
    return rss_joint <= rss_separate;
  const auto count = static_cast<double>(n);
  return count * std::log(rss_joint / rss_separate) <= saved_parameters * std::log(count);
}

int parameterCount(PrimitiveType type) {
  switch (type) {
    case PrimitiveType::plane:
      return 3;
    case PrimitiveType::sphere:
      return 4;
    case PrimitiveType::cylinder:
      return 5;
    case PrimitiveType::cone:
      return 6;
    case PrimitiveType::torus:
      return 7;
  }
  return 7;
}

std::optional<std::size_t> selectSimplest(const std::vector<ModelCandidate>& candidates,
                                          double floor) {
  double best = std::numeric_limits<double>::infinity();
  for (const ModelCandidate& c : candidates)
    if (std::isfinite(c.rms))
      best = std::min(best, c.rms);
  if (!std::isfinite(best))
    return std::nullopt;
  const double limit = (1.0 + kAdequacyMargin) * best + std::max(0.0, floor);
  std::optional<std::size_t> chosen;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const ModelCandidate& c = candidates[i];
    if (!(std::isfinite(c.rms) && c.rms <= limit))
      continue;
    if (!chosen)
      chosen = i;
    else {
      const ModelCandidate& b = candidates[*chosen];
      const int pc = parameterCount(c.type), pb = parameterCount(b.type);
      if (pc < pb || (pc == pb && c.rms < b.rms))
        chosen = i;
    }
  }
  return chosen;
}

}  // namespace slipfit
