// configs/torus.yaml end to end: points, stitched mesh (OFF with normals, PLY), naive mesh.
#include <OpenMesh/Core/IO/MeshIO.hh>  // before any OpenMesh mesh type

#include "run_cli.h"
#include "slipfit/pipeline/cloud_io.h"
#include "slipfit/surfaces/torus.h"
#include "slipfit/surfaces/torus_mesh.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace slipfit::testing {
namespace {

using ::testing::HasSubstr;

TEST(TorusCli, ConfigWritesPointsAndMeshes) {
  const std::string out = scratchDir("torus");
  const CliResult r = runSlipfit("run configs/torus.yaml --set output.dir=" + out);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("torus quarter 0 sites [w; x, y, z]: [1; 1.3, 0, 0] [0; 0, 1.3, 0] "
                               "[1; -1.3, 0, 0] [0; 0, 0, 0.3] [0; 0, 0, 0] [0; 0, 0, 0.3] "
                               "[1; 0.7, 0, 0] [0; 0, 0.7, 0] [1; -0.7, 0, 0]"));

  const auto cloud = pipeline::readCloud(out + "/torus_points.ply", pipeline::NanPolicy::error);
  ASSERT_EQ(cloud.size(), 20000u);
  ASSERT_TRUE(cloud.has_normals);
  const TorusShape torus{1.0, 0.3};
  for (const auto& p : cloud.cloud->points)
    ASSERT_LE(std::abs(torusImplicit(torus, p.getVector3fMap().cast<double>())), 1e-6);

  for (const char* name : {"/torus_mesh.off", "/torus_mesh.ply"}) {
    SurfaceMesh mesh;
    mesh.request_vertex_normals();
    OpenMesh::IO::Options options = OpenMesh::IO::Options::VertexNormal;
    ASSERT_TRUE(OpenMesh::IO::read_mesh(mesh, out + name, options)) << name;
    EXPECT_EQ(mesh.n_vertices(), 32u * 64) << name;
    EXPECT_EQ(mesh.n_faces(), 32u * 64) << name;
    EXPECT_TRUE(options.check(OpenMesh::IO::Options::VertexNormal)) << name << " lost its normals";
    for (const auto e : mesh.edges())
      ASSERT_FALSE(mesh.is_boundary(e)) << name;
  }
  const std::string off = slurp(out + "/torus_mesh.off");
  EXPECT_THAT(off.substr(0, 5), HasSubstr("NOFF"));
  // The OFF's text reads back to the sampler's doubles: every vertex on the torus to within the
  // rounding of |p|^2 terms of size (R + r)^2 = 1.69 (a few 1e-16), where OpenMesh's float
  // writer gave 3e-8 (and 6 digits 6e-6).
  std::istringstream text(off);
  std::string magic;
  std::size_t vertices = 0, faces = 0, edges = 0;
  text >> magic >> vertices >> faces >> edges;
  ASSERT_EQ(vertices, 32u * 64);
  double worst = 0.0;
  for (std::size_t v = 0; v < vertices; ++v) {
    Eigen::Vector3d p, n;
    text >> p.x() >> p.y() >> p.z() >> n.x() >> n.y() >> n.z();
    ASSERT_TRUE(text) << "vertex " << v;
    worst = std::max(worst, std::abs(torusImplicit(torus, p)));
  }
  EXPECT_LE(worst, 1e-13);
  SurfaceMesh naive;
  ASSERT_TRUE(OpenMesh::IO::read_mesh(naive, out + "/torus_mesh_naive.off"));
  EXPECT_EQ(naive.n_vertices(), 4u * 17 * 33);
}

TEST(TorusCli, BadTorusParametersAreConfigErrors) {
  CliResult r = runSlipfit("validate configs/torus.yaml --set torus.minor_radius=1.5");
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(
      r.err,
      HasSubstr("stage 'torus' (torus_sampling): torus: need 0 < minor_radius < major_radius"));
  r = runSlipfit("validate configs/torus.yaml --set torus.mesh_alpha=2");
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("key 'mesh_alpha': must be in [3, 100000], got 2"));
  r = runSlipfit("validate configs/torus.yaml --set torus.noise=-0.1");
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("key 'noise': must be in [0, inf), got -0.1"));
  r = runSlipfit(
      "validate configs/torus.yaml --set torus.mesh_alpha=31 --set torus.mesh_naive=true");
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("even resolutions"));
}

}  // namespace
}  // namespace slipfit::testing
