// configs/classify.yaml on the sample clouds, and the demo's per-point slippage fields.
#include "run_cli.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

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
    if (std::string(type) == "torus") {
      EXPECT_EQ(p["status"].as<std::string>(), "not_fitted");
      EXPECT_EQ(motions, 1);
    } else {
      EXPECT_EQ(p["status"].as<std::string>(), "ok") << cloud;
      EXPECT_GT(p["rms_distance"].as<double>(), 0.0);
    }
  }
}

TEST(SlippageCli, DemoWritesPerPointSlippageFields) {
  const std::string out = scratchDir("demo_slippage");
  const CliResult r = runSlipfit("run configs/demo.yaml --set output.dir=" + out);
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
