#include "slipfit/pipeline/config.h"
#include "slipfit/pipeline/errors.h"
#include "slipfit/pipeline/registry.h"

#include "run_cli.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace slipfit::pipeline {
namespace {

using ::testing::HasSubstr;

std::string configError(const std::string& yaml, const std::vector<std::string>& overrides = {}) {
  const std::string path = testing::scratchFile("config_test.yaml", yaml);
  try {
    loadConfig(path, overrides);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

const char* kGood =
    "input: {path: sample_clouds/demo_scene.ply}\n"
    "stages:\n"
    "  - type: neighborhood_selection\n"
    "    tag: nb\n"
    "    k: 12\n"
    "  - type: normal_estimation\n"
    "    orientation: consistent\n"
    "output: {dir: out/x}\n";

TEST(Config, LoadsStagesWithTagsAndOptions) {
  const std::string path = testing::scratchFile("good.yaml", kGood);
  const PipelineConfig c = loadConfig(path, {});
  ASSERT_EQ(c.stages.size(), 2u);
  EXPECT_EQ(c.stages[0].tag, "nb");
  EXPECT_EQ(c.stages[1].tag, "normal_estimation");  // the type when no tag is given
  EXPECT_EQ(c.input.path, "sample_clouds/demo_scene.ply");
  EXPECT_EQ(c.output.dir, "out/x");
  EXPECT_EQ(c.output.format, PlyEncoding::binary);
}

TEST(Config, SetOverridesFileValues) {
  const std::string path = testing::scratchFile("good.yaml", kGood);
  const PipelineConfig c = loadConfig(
      path, {"input.path=a.ply", "output.dir=elsewhere", "output.format=ascii", "threads=1"});
  EXPECT_EQ(c.input.path, "a.ply");
  EXPECT_EQ(c.output.dir, "elsewhere");
  EXPECT_EQ(c.output.format, PlyEncoding::ascii);
  EXPECT_EQ(c.settings.threads, 1);
  EXPECT_THAT(configError(kGood, {"nb.k=2"}),
              HasSubstr("--set nb.k=2: stage 'nb' (neighborhood_selection): key 'k': must be in "
                        "[3, 10000], got 2"));
  EXPECT_THAT(configError(kGood, {"nb.kk=20"}),
              HasSubstr("--set nb.kk=20: stage 'nb' (neighborhood_selection): unknown key 'kk'"));
  EXPECT_THAT(configError(kGood, {"normals.k=20"}),
              HasSubstr("no stage is tagged 'normals'; tags: nb, normal_estimation"));
  EXPECT_THAT(configError(kGood, {"k20"}), HasSubstr("expected KEY=VALUE"));
}

TEST(Config, UnknownKeyNamesTheLineAndTheValidKeys) {
  const std::string e = configError(
      "input: {path: x.ply}\n"
      "stages:\n"
      "  - type: neighborhood_selection\n"
      "    kk: 12\n");
  EXPECT_THAT(e,
              HasSubstr("config_test.yaml:4:5: stage 'neighborhood_selection' "
                        "(neighborhood_selection): unknown key 'kk'; valid keys: mode, k, radius"));
}

TEST(Config, UnknownStageListsTheKnownOnes) {
  const std::string e = configError("input: {path: x.ply}\nstages:\n  - type: normal_estimaton\n");
  EXPECT_THAT(
      e, HasSubstr("config_test.yaml:3:11: unknown stage type 'normal_estimaton'; known stages: " +
                   knownStagesText()));
}

TEST(Config, BadValuesNameKeyAndLine) {
  EXPECT_THAT(
      configError(
          "input: {path: x.ply}\nstages:\n  - type: neighborhood_selection\n    mode: fast\n"),
      HasSubstr(":4:11: stage 'neighborhood_selection' (neighborhood_selection): key 'mode': "
                "'fast' is not one of knn, radius, hybrid, adaptive"));
  EXPECT_THAT(
      configError("input: {path: x.ply}\nstages:\n  - type: normal_estimation\n    k: [1]\n"),
      HasSubstr(":4:8: stage 'normal_estimation' (normal_estimation): key 'k': expected a "
                "single int value, got a list"));
  // Cross-option checks run before anything else: radius mode without a radius.
  EXPECT_THAT(
      configError(
          "input: {path: x.ply}\nstages:\n  - type: neighborhood_selection\n    mode: radius\n"),
      HasSubstr(":3:5: stage 'neighborhood_selection' (neighborhood_selection): neighborhood "
                "parameters: radius = unset violates"));
}

TEST(Config, StructureErrors) {
  EXPECT_THAT(configError("stages: []\n"),
              HasSubstr("no input section and no stage that makes points"));
  EXPECT_THAT(configError("input: {nan: skip}\nstages: []\n"),
              HasSubstr("section 'input': missing required key 'path'"));
  EXPECT_THAT(configError("input: {path: x.ply}\n"), HasSubstr("missing 'stages' list"));
  EXPECT_THAT(configError("input: {path: x.ply}\nstages: []\nouptut: {}\n"),
              HasSubstr(":3:1: unknown top-level key 'ouptut'"));
  EXPECT_THAT(configError("input: {path: x.ply}\nstages:\n  - type: normal_estimation\n  - type: "
                          "normal_estimation\n"),
              HasSubstr("stage tag 'normal_estimation' is used twice"));
  EXPECT_THAT(configError("input: {path: x.ply\nstages: []\n"), HasSubstr("YAML syntax error"));
  EXPECT_THAT(
      configError("input: {path: x.ply}\nstages:\n  - type: normal_estimation\n    threads: 2\n"),
      HasSubstr("unknown key 'threads'"));
  EXPECT_THAT(configError("- a\n- b\n"), HasSubstr("must be a YAML map"));
}

TEST(Config, RepeatedKeysAreErrors) {
  EXPECT_THAT(
      configError(
          "input: {path: x.ply}\nstages:\n  - type: neighborhood_selection\n    k: 5\n    k: 6\n"),
      HasSubstr(
          ":5:5: stage 'neighborhood_selection' (neighborhood_selection): key 'k' is given twice"));
  EXPECT_THAT(
      configError("input: {path: x.ply}\nstages:\n  - type: primitive_sampling\n    type: plane\n"),
      HasSubstr("key 'type' is given twice"));
}

TEST(Config, MissingConfigFile) {
  EXPECT_THROW(loadConfig("/nonexistent/slipfit.yaml", {}), ConfigError);
}

}  // namespace
}  // namespace slipfit::pipeline
