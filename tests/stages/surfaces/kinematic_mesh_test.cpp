// kinematicMesh: the fitted profile swept by its motion lies on the fitted surface, covers the
// points and stops where they stop.

#include "slipfit/surfaces/kinematic_mesh.h"
#include "slipfit/core/name_table.h"
#include "slipfit/fitting/kinematic_fit.h"
#include "slipfit/sampling/motion_surface_sampler.h"

#include "motion_surface_types.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace slipfit {
namespace {

struct Fitted {
  MotionSurfaceParameters m;
  Eigen::Matrix3Xd points;
  KinematicSurface surface;
};

Fitted fitted(MotionSurface surface, KinematicType type) {
  Fitted f;
  f.m.surface = surface;
  f.m.points = 4000;
  f.m.noise = 0.002;
  f.m.seed = 7;
  f.m.center = Eigen::Vector3d(0.4, -1.0, 2.0);
  f.m.axis = Eigen::Vector3d(1.0, 0.5, 2.0);
  Eigen::Matrix3Xd normals;
  sampleMotionSurface(f.m, f.points, normals);
  KinematicStart start;
  start.type = type;
  start.axis = f.m.axis;
  start.point = f.m.center;
  start.pitch = f.m.pitch;
  const KinematicFit fit =
      fitKinematicSurface(start, f.points, Eigen::VectorXd::Ones(f.points.cols()), f.m.noise);
  EXPECT_TRUE(fit.ok()) << fit.reason;
  f.surface = fit.surface;
  return f;
}

Eigen::Vector3d toEigen(const OpenMesh::Vec3d& p) {
  return {p[0], p[1], p[2]};
}

/// The longest mesh edge: a point of the surface the mesh covers is within it of a vertex.
double longestEdge(const SurfaceMesh& mesh) {
  double longest = 0.0;
  for (const auto e : mesh.edges())
    longest = std::max(longest, mesh.calc_edge_length(e));
  return longest;
}

double nearest(const Eigen::Vector3d& q, const Eigen::Matrix3Xd& to) {
  return std::sqrt((to.colwise() - q).colwise().squaredNorm().minCoeff());
}

// Every vertex is a profile vertex moved by the motion, so it is on the fitted surface (to
// rounding); every point is within the longest edge (+ 4 σ of noise) of a vertex: the mesh covers
// the points; and every vertex is within the longest edge (+ 4 σ) of a point: it does not run on
// past them (a helix swept over its screw angle ran a turn, 1.57 units, past a twisted column).
TEST(KinematicMesh, LiesOnTheFittedSurfaceAndCoversThePointsOnly) {
  for (const auto& [surface, surface_name] : kMotionSurfaceNames) {
    const KinematicType type = testing::kinematicTypeOf(surface);
    const std::string name(surface_name);
    const Fitted f = fitted(surface, type);
    const SurfaceMesh mesh = kinematicMesh(f.surface, f.points, 96);
    const std::size_t v = f.surface.profile.vertices.size();
    const std::size_t rings = type == KinematicType::revolution ? 96 : 97;
    EXPECT_EQ(mesh.n_vertices(), rings * v) << name;
    EXPECT_EQ(mesh.n_faces(), 96 * f.surface.profile.segmentCount()) << name;
    Eigen::Matrix3Xd vertices(3, static_cast<Eigen::Index>(mesh.n_vertices()));
    double off_surface = 0.0;
    for (const auto h : mesh.vertices()) {
      vertices.col(h.idx()) = toEigen(mesh.point(h));
      off_surface = std::max(off_surface, distance(vertices.col(h.idx()), f.surface));
    }
    EXPECT_LE(off_surface, 1e-9) << name;
    const double reach = longestEdge(mesh) + 4.0 * f.m.noise;
    double uncovered = 0.0, overrun = 0.0;
    for (Eigen::Index i = 0; i < f.points.cols(); i += 7)
      uncovered = std::max(uncovered, nearest(f.points.col(i), vertices));
    for (Eigen::Index i = 0; i < vertices.cols(); ++i)
      overrun = std::max(overrun, nearest(vertices.col(i), f.points));
    EXPECT_LE(uncovered, reach) << name;
    EXPECT_LE(overrun, reach) << name;
  }
}

// The vase's points go all the way round: the mesh closes (96 rings, no seam). Half of them, on
// one side of a plane through the axis, give a sweep of π less at most two steps.
TEST(KinematicMesh, ARevolutionClosesOnlyWhenThePointsGoRound) {
  const Fitted f = fitted(MotionSurface::revolution, KinematicType::revolution);
  const SurfaceMesh whole = kinematicMesh(f.surface, f.points, 96);
  EXPECT_EQ(whole.n_vertices(), 96 * f.surface.profile.vertices.size());
  const Eigen::Vector3d across = f.surface.axis.unitOrthogonal();
  std::vector<Eigen::Index> half;
  for (Eigen::Index i = 0; i < f.points.cols(); ++i)
    if ((f.points.col(i) - f.surface.point).dot(across) > 0.0)
      half.push_back(i);
  const Eigen::Matrix3Xd side = f.points(Eigen::all, half);
  const SurfaceMesh open = kinematicMesh(f.surface, side, 96);
  EXPECT_EQ(open.n_vertices(), 97 * f.surface.profile.vertices.size());
  // The sweep's angle: between the first and the last ring's first vertex, about the axis.
  const auto first = toEigen(open.point(open.vertex_handle(0)));
  const auto last = toEigen(open.point(
      open.vertex_handle(static_cast<unsigned>(96 * f.surface.profile.vertices.size()))));
  const Eigen::Vector3d a =
      (first - f.surface.point) - (first - f.surface.point).dot(f.surface.axis) * f.surface.axis;
  const Eigen::Vector3d b =
      (last - f.surface.point) - (last - f.surface.point).dot(f.surface.axis) * f.surface.axis;
  const double swept = std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0));
  EXPECT_NEAR(swept, M_PI, 2.0 * (2.0 * M_PI / 96));
}

TEST(KinematicMesh, EmptyProfileNoPointsOrNoStepsAreRefused) {
  const Fitted f = fitted(MotionSurface::extrusion, KinematicType::extrusion);
  KinematicSurface empty = f.surface;
  empty.profile.vertices.clear();
  EXPECT_THROW(kinematicMesh(empty, f.points, 8), std::invalid_argument);
  EXPECT_THROW(kinematicMesh(f.surface, Eigen::Matrix3Xd(3, 0), 8), std::invalid_argument);
  EXPECT_THROW(kinematicMesh(f.surface, f.points, 0), std::invalid_argument);
}

}  // namespace
}  // namespace slipfit
