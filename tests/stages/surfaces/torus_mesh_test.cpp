#include "slipfit/surfaces/torus_mesh.h"
#include "slipfit/core/angle_units.h"

#include "slipfit/core/exceptions.h"

#include <gtest/gtest.h>

#include <cmath>
#include <queue>

namespace slipfit {
namespace {

const TorusShape kTorus{2.0, 0.7};

Eigen::Vector3d eig(const OpenMesh::Vec3d& v) {
  return {v[0], v[1], v[2]};
}

std::size_t components(const SurfaceMesh& mesh) {
  std::vector<char> seen(mesh.n_vertices(), 0);
  std::size_t count = 0;
  for (const auto start : mesh.vertices()) {
    if (seen[start.idx()])
      continue;
    ++count;
    std::queue<SurfaceMesh::VertexHandle> q;
    q.push(start);
    seen[start.idx()] = 1;
    while (!q.empty()) {
      const auto v = q.front();
      q.pop();
      for (const auto w : mesh.vv_range(v))
        if (!seen[w.idx()]) {
          seen[w.idx()] = 1;
          q.push(w);
        }
    }
  }
  return count;
}

double angleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / kPi;
}

class TorusMeshTest : public ::testing::TestWithParam<TorusSpacing> {};

TEST_P(TorusMeshTest, ClosedManifoldOutwardWithAnalyticNormals) {
  TorusMeshParameters p;
  p.n_alpha = 24;
  p.n_beta = 40;
  p.spacing = GetParam();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(10, -5, 3);
  const SurfaceMesh mesh = torusMesh(kTorus, p, pose);

  const std::size_t n = 24 * 40;
  EXPECT_EQ(mesh.n_vertices(), n) << "seam vertices must exist once";
  EXPECT_EQ(mesh.n_faces(), n);
  EXPECT_EQ(mesh.n_edges(), 2 * n);
  EXPECT_EQ(static_cast<long>(mesh.n_vertices()) - static_cast<long>(mesh.n_edges()) +
                static_cast<long>(mesh.n_faces()),
            0)
      << "Euler characteristic of a torus";
  for (const auto e : mesh.edges())
    ASSERT_FALSE(mesh.is_boundary(e)) << "every edge has two faces";
  EXPECT_EQ(components(mesh), 1u);

  const Eigen::Isometry3d inverse = pose.inverse();
  for (const auto f : mesh.faces()) {
    ASSERT_EQ(mesh.valence(f), 4u);
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const auto v : mesh.fv_range(f))
      centroid += eig(mesh.point(v)) / 4.0;
    const Eigen::Vector3d local = inverse * centroid;
    const Eigen::Vector3d on_circle =
        kTorus.R * Eigen::Vector3d(local.x(), local.y(), 0).normalized();
    const Eigen::Vector3d away = pose.linear() * (local - on_circle);
    ASSERT_GT(eig(mesh.normal(f)).dot(away), 0.0) << "face normal must point out of the tube";
  }
  double worst_face_avg = 0.0;
  for (const auto v : mesh.vertices()) {
    const Eigen::Vector3d x = inverse * eig(mesh.point(v));
    ASSERT_LE(std::abs(torusImplicit(kTorus, x)), 1e-12 * kTorus.R * kTorus.R);
    const double a = std::atan2(x.z(), std::hypot(x.x(), x.y()) - kTorus.R),
                 b = std::atan2(x.y(), x.x());
    ASSERT_LT(angleDeg(eig(mesh.normal(v)), pose.linear() * torusNormal(a, b)), 0.5);
    // No shading cusp: the vertex normal agrees with the mean of its faces' normals, on the seams
    // as elsewhere, to within one grid step.
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto f : mesh.vf_range(v))
      mean += eig(mesh.normal(f));
    worst_face_avg = std::max(worst_face_avg, angleDeg(eig(mesh.normal(v)), mean));
  }
  EXPECT_LT(worst_face_avg, 360.0 / 24);
}

INSTANTIATE_TEST_SUITE_P(Spacings, TorusMeshTest,
                         ::testing::Values(TorusSpacing::angle, TorusSpacing::parameter),
                         [](const auto& info) {
                           return info.param == TorusSpacing::angle ? "angle" : "parameter";
                         });

TEST(TorusMesh, NaiveVariantDuplicatesTheSeams) {
  TorusMeshParameters p;
  p.n_alpha = 8;
  p.n_beta = 12;
  const SurfaceMesh naive = torusMeshNaive(kTorus, p);
  EXPECT_EQ(naive.n_vertices(), 4u * 5 * 7);
  EXPECT_EQ(naive.n_faces(), 8u * 12);
  std::size_t boundary = 0;
  for (const auto e : naive.edges())
    boundary += naive.is_boundary(e) ? 1 : 0;
  EXPECT_GT(boundary, 0u) << "the quarters are not stitched";
  EXPECT_EQ(components(naive), 4u);
}

TEST(TorusMesh, GridAnglesOfParameterSpacingFollowThePatches) {
  // Parameter spacing puts vertices at u = i/(n/2): the seams at α = 0 and π, and V(1/2) at π/2.
  EXPECT_DOUBLE_EQ(torusGridAngle(0, 8, TorusSpacing::parameter), 0.0);
  EXPECT_NEAR(torusGridAngle(2, 8, TorusSpacing::parameter), kPi / 2, 1e-15);
  EXPECT_NEAR(torusGridAngle(4, 8, TorusSpacing::parameter), kPi, 1e-15);
  EXPECT_NEAR(torusGridAngle(6, 8, TorusSpacing::parameter), 1.5 * kPi, 1e-15);
  // Not arc-length uniform: the first step is 2 atan(1/3), not π/4.
  EXPECT_NEAR(torusGridAngle(1, 8, TorusSpacing::parameter), 2 * std::atan(1.0 / 3.0), 1e-15);
}

TEST(TorusMesh, BadParametersThrow) {
  TorusMeshParameters p;
  p.n_alpha = 2;
  EXPECT_THROW(torusMesh(kTorus, p), InvalidParameterError);
  p.n_alpha = 7;
  p.spacing = TorusSpacing::parameter;
  EXPECT_THROW(torusMesh(kTorus, p), InvalidParameterError);
  EXPECT_THROW(torusMesh(TorusShape{1.0, 2.0}, TorusMeshParameters{}), InvalidParameterError);
}

}  // namespace
}  // namespace slipfit
