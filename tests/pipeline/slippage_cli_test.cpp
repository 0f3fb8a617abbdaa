// configs/classify.yaml on the sample clouds, and the demo's per-point slippage fields.
#include "run_cli.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <pcl/PolygonMesh.h>
#include <pcl/io/ply_io.h>

#include <Eigen/Core>

#include <cmath>
#include <filesystem>

namespace slipfit::testing {
namespace {

using ::testing::HasSubstr;

TEST(SlippageCli, WholeCloudVerdictsOfTheSampleClouds) {
  const std::pair<const char*, const char*> cases[] = {{"plane", "plane"},
                                                       {"sphere", "sphere"},
                                                       {"cylinder", "cylinder"},
                                                       {"cone", "cone"},
                                                       {"torus_normals", "torus"}};
  for (const auto& [cloud, type] : cases) {
    const std::string out = scratchDir(std::string("classify_") + cloud);
    const CliResult r =
        runSlipfit(std::string("run configs/classify.yaml --set input.path=sample_clouds/") +
                   cloud + ".ply --set output.dir=" + out);
    ASSERT_EQ(r.code, 0) << r.err;
    const YAML::Node p = YAML::LoadFile(out + "/primitives.yaml")["primitives"][0];
    EXPECT_EQ(p["slippage_type"].as<std::string>(), type) << cloud;
    EXPECT_EQ(p["type"].as<std::string>(), type) << cloud;
    EXPECT_EQ(p["spectrum"].size(), 6u);
    const int motions = p["slippable_motions"].as<int>();
    EXPECT_EQ(p["status"].as<std::string>(), "ok") << cloud;
    EXPECT_GT(p["rms_distance"].as<double>(), 0.0);
    if (std::string(type) == "torus") {
      // The sample torus: about z through the origin, R = 1, r = 0.35, stored as float
      // (6e-8 relative rounding): the fit recovers it to 1e-6.
      EXPECT_EQ(motions, 1);
      EXPECT_NEAR(p["major_radius"].as<double>(), 1.0, 1e-6);
      EXPECT_NEAR(p["minor_radius"].as<double>(), 0.35, 1e-6);
      EXPECT_NEAR(std::abs(p["axis"][2].as<double>()), 1.0, 1e-9);
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(p["center"][k].as<double>(), 0.0, 1e-6);
    }
  }
}

// A mesh is asked for, but a sphere's verdict is a primitive: no mesh file, and the report says
// why.
TEST(SlippageCli, NoMeshWhenTheVerdictIsAPrimitive) {
  const std::string out = scratchDir("classify_no_mesh");
  const CliResult r = runSlipfit(
      "run configs/classify.yaml --set input.path=sample_clouds/"
      "sphere.ply --set slippage.mesh=true --set output.dir=" +
      out);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("mesh: none (the verdict is not a fitted kinematic surface)"));
  EXPECT_FALSE(std::filesystem::exists(out + "/kinematic.ply"));
  EXPECT_TRUE(std::filesystem::exists(out + "/primitives.yaml"));
}

TEST(SlippageCli, OneMotionSurfacesFromTheSurfaceSampler) {
  const std::pair<const char*, const char*> cases[] = {{"helix", "helix"},
                                                       {"revolution", "revolution"},
                                                       {"extrusion", "extrusion"},
                                                       {"open_extrusion", "extrusion"},
                                                       {"twisted_column", "helix"}};
  for (const auto& [shape, type] : cases) {
    const std::string out = scratchDir(std::string("one_motion_") + shape);
    const CliResult r =
        runSlipfit(std::string("run configs/classify_helix.yaml --set surface.shape=") + shape +
                   " --set slippage.mesh=true --set output.dir=" + out);
    ASSERT_EQ(r.code, 0) << r.err;
    const YAML::Node p = YAML::LoadFile(out + "/primitives.yaml")["primitives"][0];
    EXPECT_EQ(p["slippage_type"].as<std::string>(), type) << shape;
    EXPECT_EQ(p["slippable_motions"].as<int>(), 1) << shape;
    // No primitive explains a one-motion surface: the answer is its kinematic class.
    EXPECT_EQ(p["status"].as<std::string>(), "not_fitted") << shape;
    const YAML::Node k = p["kinematic"];
    ASSERT_TRUE(k.IsMap()) << shape;
    EXPECT_EQ(k["class"].as<std::string>(), type) << shape;
    const Eigen::Vector3d axis(k["axis"][0].as<double>(), k["axis"][1].as<double>(),
                               k["axis"][2].as<double>());
    EXPECT_GT(std::abs(axis.dot(Eigen::Vector3d(1, 0, 1).normalized())),
              std::cos(3.14159265358979323846 / 180))
        << shape;
    // The sampler's pitch is 0.25 per radian; a pure rotation or translation reports 0.
    EXPECT_NEAR(std::abs(k["pitch"].as<double>()), std::string(type) == "helix" ? 0.25 : 0.0,
                0.0025)
        << shape;
    // The fitted surface (kinematic_fit.h): its profile, and its RMS distance at the sampler's
    // σ = 0.002 (Gaussian noise: the true surface's RMS is σ; the fit, a few dozen parameters for
    // 5000 points, within 0.8–1.25 σ). Its axis passes through the sampler's centre (1, 2, 3).
    ASSERT_TRUE(k["profile"].IsSequence()) << shape;
    EXPECT_GE(k["profile"].size(), 2u) << shape;
    EXPECT_NEAR(k["rms_distance"].as<double>(), 0.002, 0.0005) << shape;
    if (std::string(type) != "extrusion") {
      const Eigen::Vector3d w =
          Eigen::Vector3d(k["point"][0].as<double>(), k["point"][1].as<double>(),
                          k["point"][2].as<double>()) -
          Eigen::Vector3d(1, 2, 3);
      EXPECT_LE((w - w.dot(axis.normalized()) * axis.normalized()).norm(), 0.01) << shape;
    }
    // The swept mesh loads in PCL: 96 steps of the profile, a quad per segment and step, and a
    // ring per step (97 rings for an open sweep; the vase goes all the way round: 96).
    pcl::PolygonMesh mesh;
    ASSERT_EQ(pcl::io::loadPLYFile(out + "/kinematic.ply", mesh), 0) << shape;
    const std::size_t v = k["profile"].size();
    const std::size_t segments = k["profile_closed"].as<bool>() ? v : v - 1;
    EXPECT_EQ(mesh.polygons.size(), 96 * segments) << shape;
    EXPECT_EQ(std::size_t{mesh.cloud.width} * mesh.cloud.height,
              (std::string(shape) == "revolution" ? 96 : 97) * v)
        << shape;
    EXPECT_THAT(r.out, HasSubstr("mesh: kinematic.ply")) << shape;
  }
}

TEST(SlippageCli, DemoWritesPerPointSlippageFields) {
  const std::string out = scratchDir("demo_slippage");
  const CliResult r = runSlipfit("run configs/normals_demo.yaml --set output.dir=" + out);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("local slippage: "));
  EXPECT_THAT(slurp(out + "/cloud.ply").substr(0, 3000),
              ::testing::AllOf(HasSubstr("property int slippable_motions"),
                               HasSubstr("property int slippage_type"),
                               HasSubstr("property float slip_axis_x"),
                               HasSubstr("property float slip_gap")));
}

TEST(SlippageCli, LocalModeNeedsNeighborhoods) {
  const CliResult r = runSlipfit("validate configs/classify.yaml --set slippage.mode=local");
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("needs neighborhoods"));
}

}  // namespace
}  // namespace slipfit::testing
