#include "slipfit/surfaces/kinematic_mesh.h"

#include "slipfit/core/angle_units.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace slipfit {

namespace {

double angleAbout(const KinematicSurface& s, const SectionFrame& f, const Eigen::Vector3d& p) {
  const Eigen::Vector3d w = p - s.point;
  return std::atan2(w.dot(f.e2), w.dot(f.e1));
}

/// The sweep's range [from, from + length] and whether it closes on itself (a revolution all the
/// way round).
struct Sweep {
  double from = 0.0, length = 0.0;
  bool closed = false;
};

Sweep sweepOf(const KinematicSurface& s, const Eigen::Ref<const Eigen::Matrix3Xd>& points,
              int steps) {
  // A helix sweeps each profile vertex over the heights along the axis the points span: over
  // their screw angles instead, vertices a period apart in the profile would run a turn past the
  // points at one end or the other (sweptPoint's t for vertex u is (h − u) / pitch).
  std::vector<double> t(static_cast<std::size_t>(points.cols()));
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    t[static_cast<std::size_t>(i)] = s.type == KinematicType::helix
                                         ? (points.col(i) - s.point).dot(s.axis)
                                         : motionParameter(s, points.col(i));
  std::sort(t.begin(), t.end());
  Sweep sweep;
  if (s.type != KinematicType::revolution) {
    sweep.from = t.front();
    sweep.length = t.back() - t.front();
    return sweep;
  }
  // The widest empty stretch of angle, the wrap included: the sweep is the rest.
  double gap = t.front() + 2.0 * kPi - t.back(), after = t.front();
  for (std::size_t k = 1; k < t.size(); ++k)
    if (t[k] - t[k - 1] > gap) {
      gap = t[k] - t[k - 1];
      after = t[k];
    }
  if (gap <= 2.0 * (2.0 * kPi / steps)) {
    sweep.closed = true;
    sweep.from = 0.0;
    sweep.length = 2.0 * kPi;
  } else {
    sweep.from = after;
    sweep.length = 2.0 * kPi - gap;
  }
  return sweep;
}

OpenMesh::Vec3d toOm(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

}  // namespace

double motionParameter(const KinematicSurface& s, const Eigen::Vector3d& p) {
  const SectionFrame f = sectionFrame(s);
  switch (s.type) {
    case KinematicType::revolution:
      return angleAbout(s, f, p);
    case KinematicType::extrusion:
      return (p - s.point).dot(s.axis);
    case KinematicType::helix: {
      const double h = (p - s.point).dot(s.axis);
      return (h - profileCoordinates(s, p).x()) / s.pitch;
    }
  }
  return 0.0;
}

Eigen::Vector3d sweptPoint(const KinematicSurface& s, const Eigen::Vector2d& v, double t) {
  const SectionFrame f = sectionFrame(s);
  switch (s.type) {
    case KinematicType::revolution:
      return s.point + v.x() * s.axis + v.y() * (std::cos(t) * f.e1 + std::sin(t) * f.e2);
    case KinematicType::extrusion:
      return s.point + v.x() * f.e1 + v.y() * f.e2 + t * s.axis;
    case KinematicType::helix:
      return s.point + (v.x() + s.pitch * t) * s.axis +
             v.y() * (std::cos(t) * f.e1 + std::sin(t) * f.e2);
  }
  return s.point;
}

SurfaceMesh kinematicMesh(const KinematicSurface& s,
                          const Eigen::Ref<const Eigen::Matrix3Xd>& points, int steps) {
  if (s.profile.vertices.empty())
    throw std::invalid_argument("kinematic mesh: the profile is empty");
  if (points.cols() == 0)
    throw std::invalid_argument("kinematic mesh: no points to say where the surface is");
  if (steps < 1)
    throw std::invalid_argument("kinematic mesh: steps must be at least 1");
  const Sweep sweep = sweepOf(s, points, steps);
  const auto nv = s.profile.vertices.size();
  const auto rings = static_cast<std::size_t>(sweep.closed ? steps : steps + 1);
  SurfaceMesh mesh;
  std::vector<SurfaceMesh::VertexHandle> v(rings * nv);
  for (std::size_t k = 0; k < rings; ++k) {
    const double t = sweep.from + sweep.length * static_cast<double>(k) / steps;
    for (std::size_t j = 0; j < nv; ++j) {
      const Eigen::Vector2d& u = s.profile.vertices[j];
      const double at = s.type == KinematicType::helix ? (t - u.x()) / s.pitch : t;
      v[k * nv + j] = mesh.add_vertex(toOm(sweptPoint(s, u, at)));
    }
  }
  const std::size_t segments = s.profile.segmentCount();
  for (std::size_t k = 0; k < static_cast<std::size_t>(steps); ++k) {
    const std::size_t k1 = (k + 1) % rings;
    for (std::size_t j = 0; j < segments; ++j) {
      const std::size_t j1 = (j + 1) % nv;
      mesh.add_face(v[k * nv + j], v[k1 * nv + j], v[k1 * nv + j1], v[k * nv + j1]);
    }
  }
  mesh.update_normals();
  return mesh;
}

}  // namespace slipfit
