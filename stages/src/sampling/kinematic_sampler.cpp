#include "slipfit/sampling/kinematic_sampler.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace slipfit {

namespace {

void check(const KinematicSurface& s, const MotionStretch& stretch) {
  if (s.profile.vertices.size() < 2)
    throw std::invalid_argument("kinematic sampler: the profile needs 2 vertices or more");
  if (!(stretch.to > stretch.from))
    throw std::invalid_argument("kinematic sampler: the stretch of the motion is empty");
  if (s.type == KinematicType::helix && !(std::abs(s.pitch) > 0.0))
    throw std::invalid_argument("kinematic sampler: a helix needs a non-zero pitch");
}

/// The area element per unit of profile arc and of motion at profile point (a, b) with unit
/// tangent (da, db): ρ for a revolution (per radian), 1 for an extrusion, √(ρ² + ρ'² pitch²) for
/// a helix (per radian of screw).
double areaElement(const KinematicSurface& s, double rho, double drho) {
  switch (s.type) {
    case KinematicType::revolution:
      return std::abs(rho);
    case KinematicType::extrusion:
      return 1.0;
    case KinematicType::helix:
      return std::sqrt(rho * rho + drho * drho * s.pitch * s.pitch);
  }
  return 1.0;
}

/// The motion's extent: radians (revolution), units (extrusion), screw radians (helix).
double motionLength(const KinematicSurface& s, const MotionStretch& stretch) {
  const double length = stretch.to - stretch.from;
  return s.type == KinematicType::helix ? length / std::abs(s.pitch) : length;
}

struct Segment {
  Eigen::Vector2d a, b;
  double length = 0.0, wa = 0.0, wb = 0.0;
};

std::vector<Segment> segments(const KinematicSurface& s) {
  std::vector<Segment> out;
  const auto& v = s.profile.vertices;
  for (std::size_t j = 0; j < s.profile.segmentCount(); ++j) {
    Segment g;
    g.a = v[j];
    g.b = v[(j + 1) % v.size()];
    g.length = (g.b - g.a).norm();
    if (!(g.length > 0.0))
      continue;
    const double drho = (g.b.y() - g.a.y()) / g.length;
    g.wa = areaElement(s, g.a.y(), drho);
    g.wb = areaElement(s, g.b.y(), drho);
    out.push_back(g);
  }
  return out;
}

}  // namespace

double kinematicArea(const KinematicSurface& s, const MotionStretch& stretch) {
  check(s, stretch);
  double area = 0.0;
  for (const Segment& g : segments(s))
    area += g.length * 0.5 * (g.wa + g.wb);
  return area * motionLength(s, stretch);
}

void sampleKinematicSurface(const KinematicSurface& s, const MotionStretch& stretch, std::size_t n,
                            std::mt19937_64& rng, Eigen::Matrix3Xd& points,
                            Eigen::Matrix3Xd& normals) {
  check(s, stretch);
  const std::vector<Segment> pieces = segments(s);
  if (pieces.empty())
    throw std::invalid_argument("kinematic sampler: the profile has no segment of length > 0");
  std::vector<double> weights;
  for (const Segment& g : pieces)
    weights.push_back(g.length * 0.5 * (g.wa + g.wb));
  std::discrete_distribution<std::size_t> pick(weights.begin(), weights.end());
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const SectionFrame f = sectionFrame(s);
  points.resize(3, static_cast<Eigen::Index>(n));
  normals.resize(3, static_cast<Eigen::Index>(n));
  for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(n); ++i) {
    const Segment& g = pieces[pick(rng)];
    // Along the segment by rejection against the larger end's area element (the element is
    // monotone in |ρ|, which is linear along the segment).
    const double top = std::max(g.wa, g.wb);
    double lambda = unit(rng);
    while (top > 0.0 && unit(rng) * top > (1.0 - lambda) * g.wa + lambda * g.wb)
      lambda = unit(rng);
    const Eigen::Vector2d q = (1.0 - lambda) * g.a + lambda * g.b;
    const Eigen::Vector2d d = (g.b - g.a) / g.length;
    const double t = unit(rng);
    Eigen::Vector3d x = s.point, ds = s.axis, dt = s.axis;
    switch (s.type) {
      case KinematicType::revolution: {
        const double theta = stretch.from + t * (stretch.to - stretch.from);
        const Eigen::Vector3d radial = std::cos(theta) * f.e1 + std::sin(theta) * f.e2;
        x = s.point + q.x() * s.axis + q.y() * radial;
        ds = d.x() * s.axis + d.y() * radial;
        dt = s.axis.cross(radial);  // × ρ, which the normalisation drops
        break;
      }
      case KinematicType::extrusion: {
        const double along = stretch.from + t * (stretch.to - stretch.from);
        x = s.point + q.x() * f.e1 + q.y() * f.e2 + along * s.axis;
        ds = d.x() * f.e1 + d.y() * f.e2;
        dt = -s.axis;  // so that dt × ds is outward for a counter-clockwise section
        break;
      }
      case KinematicType::helix: {
        const double from = (stretch.from - q.x()) / s.pitch, to = (stretch.to - q.x()) / s.pitch;
        const double phi = from + t * (to - from);
        const Eigen::Vector3d radial = std::cos(phi) * f.e1 + std::sin(phi) * f.e2;
        x = s.point + (q.x() + s.pitch * phi) * s.axis + q.y() * radial;
        ds = d.x() * s.axis + d.y() * radial;
        dt = s.pitch * s.axis + q.y() * s.axis.cross(radial);
        break;
      }
    }
    Eigen::Vector3d normal = dt.cross(ds);
    if (s.type == KinematicType::revolution && q.y() < 0.0)
      normal = -normal;
    points.col(i) = x;
    normals.col(i) = normal.normalized();
  }
}

}  // namespace slipfit
