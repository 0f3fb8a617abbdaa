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

// Issue 40: --set VALUE is text read by the option's type, never YAML: a "#" is not a comment, a
// "!!" not a tag, a "*" not an alias; quotes around the whole value are taken off; a vec3 option
// parses its list; a number option refuses text that is not a number.
TEST(Config, SetValuesAreTextReadByTheOptionsType) {
  const std::string path = testing::scratchFile("good.yaml", kGood);
  PipelineConfig c = loadConfig(path, {"output.dir=results #3", "input.path=my scan #2.ply"});
  EXPECT_EQ(c.output.dir, "results #3");
  EXPECT_EQ(c.input.path, "my scan #2.ply");
  c = loadConfig(path, {"output.dir=!!binary abc", "input.path=*x", "tiling.workdir=&a [b]"});
  EXPECT_EQ(c.output.dir, "!!binary abc");
  EXPECT_EQ(c.input.path, "*x");
  EXPECT_EQ(c.tiling.workdir, "&a [b]");
  c = loadConfig(path, {"output.cloud=\"\"", "output.dir='a b'", "nb.k=20"});
  EXPECT_EQ(c.output.cloud, "");
  EXPECT_EQ(c.output.dir, "a b");
  c = loadConfig(path, {"normal_estimation.viewpoint=[1, 2.5, -3]"});
  EXPECT_THAT(configError(kGood, {"nb.k=20 #3"}),
              HasSubstr("--set nb.k=20 #3: stage 'nb' (neighborhood_selection): key 'k': "
                        "expected an integer, got '20 #3'"));
  EXPECT_THAT(configError(kGood, {"normal_estimation.viewpoint=1, 2, 3"}),
              HasSubstr("key 'viewpoint': expected a list of three numbers like [0, 0, 1]"));
  EXPECT_THAT(configError(kGood, {"normal_estimation.viewpoint=[1, 2"}),
              HasSubstr("key 'viewpoint': expected a list of three numbers like [0, 0, 1], got "
                        "'[1, 2'"));
}

// A stage tagged as a section could not be reached by --set (TAG.KEY would set the section).
TEST(Config, AStageTagThatIsASectionsNameIsRefused) {
  for (const char* tag : {"output", "input", "tiling", "stages"})
    EXPECT_THAT(
        configError(std::string("stages: [{type: neighborhood_selection, tag: ") + tag + "}]\n"),
        HasSubstr(std::string("stage tag '") + tag + "' is the name of a section"));
}

// YAML limits: aliases that expand past 10^6 nodes (a "billion laughs" of 666 bytes), nesting
// past 64 levels, and a second document are refused in one line that names the limit, before
// anything is built from them; configs within the limits load as before.
TEST(Config, YamlThatExpandsOrNestsPastTheLimitsIsRefused) {
  std::string bomb = "a: &a [x, x, x, x, x, x, x, x, x, x]\n";
  for (char name = 'b'; name <= 'i'; ++name) {
    const char previous = static_cast<char>(name - 1);
    bomb += std::string(1, name) + ": &" + name + " [";
    for (int k = 0; k < 10; ++k)
      bomb += std::string(k ? ", " : "") + "*" + previous;
    bomb += "]\n";
  }
  bomb += "stages: [{type: neighborhood_selection}]\n";
  ASSERT_LT(bomb.size(), 700u);  // 10^9 leaves once expanded
  EXPECT_THAT(configError(bomb), HasSubstr("config_test.yaml:6: the YAML expands to more than "
                                           "1000000 nodes"));
  // Nesting: 64 levels load (and fail later for what they are), 65 do not.
  const auto nested = [](int levels) {
    return "stages: [{type: neighborhood_selection}]\nseed: " + std::string(levels, '[') +
           std::string(levels, ']') + "\n";
  };
  EXPECT_THAT(configError(nested(63)), ::testing::Not(HasSubstr("levels")));
  EXPECT_THAT(configError(nested(64)), HasSubstr("the YAML nests deeper than 64 levels"));
  EXPECT_THAT(configError(nested(600)), HasSubstr("config_test.yaml:2: the YAML nests deeper"));
  // An alias that brings a deep node deeper.
  EXPECT_THAT(configError("a: &a " + std::string(40, '[') + std::string(40, ']') + "\nb: " +
                          std::string(30, '[') + "*a" + std::string(30, ']') + "\nstages: []\n"),
              HasSubstr("nests deeper than 64 levels once its aliases are expanded"));
  // An alias inside the anchor it names: a cycle every walk of the config would follow forever
  // (found by fuzz.config: a stack overflow).
  EXPECT_THAT(configError("a: &a [x, *a]\nstages: []\n"),
              HasSubstr("config_test.yaml:1: the YAML has an alias inside the anchor it names"));
  EXPECT_THAT(configError("a: &m {b: {c: *m}}\nstages: []\n"), HasSubstr("(a cycle)"));
  EXPECT_THAT(configError(std::string(kGood) + "---\nstages: []\n"),
              HasSubstr("config_test.yaml:9: a second YAML document (after '---')"));
  // Anchors and aliases within the limits are still read.
  const std::string path = testing::scratchFile(
      "aliases.yaml",
      "input: {path: &p a.ply}\noutput: {dir: *p}\nstages: [{type: neighborhood_selection}]\n");
  EXPECT_EQ(loadConfig(path, {}).output.dir, "a.ply");
}

}  // namespace
}  // namespace slipfit::pipeline
