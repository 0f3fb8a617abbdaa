// End-to-end tests of the `slipfit` executable: what a user types, what they see, what is left on
// disk.
#include "run_cli.h"

#include "slipfit/pipeline/cloud_io.h"
#include "slipfit/pipeline/registry.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

namespace slipfit::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::StartsWith;

std::size_t lines(const std::string& s) {
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

/// Files left in \a dir (none when it does not exist).
std::size_t filesIn(const std::string& dir) {
  if (!fs::exists(dir))
    return 0;
  return static_cast<std::size_t>(
      std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

TEST(Cli, DemoConfigRunsAndWritesOrientedNormals) {
  const std::string out = scratchDir("demo");
  const CliResult r = runSlipfit("run configs/normals_demo.yaml --set output.dir=" + out);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");  // piped: no progress
  EXPECT_THAT(r.out, HasSubstr("input: sample_clouds/demo_scene.ply: 42000 points, normals: no"));
  EXPECT_THAT(r.out, HasSubstr("neighborhoods: 42000 points, sizes 16..16"));
  EXPECT_THAT(r.out, HasSubstr("wrote " + out + "/cloud.ply"));
  ASSERT_EQ(filesIn(out), 1u);

  const auto data = pipeline::readCloud(out + "/cloud.ply", pipeline::NanPolicy::error);
  ASSERT_EQ(data.size(), 42000u);
  ASSERT_TRUE(data.has_normals);
  EXPECT_THAT(
      slurp(out + "/cloud.ply").substr(0, 2000),
      ::testing::AllOf(HasSubstr("property float nx"), HasSubstr("property int neighbors"),
                       HasSubstr("property float scale"), HasSubstr("property float curvature")));
  // The sample scene (sample_clouds/README.md): ground plane z = 0, sphere at (-0.9, 0.8, 0.9)
  // r = 0.5. Ground normals face the viewpoint above; the sphere's point outward.
  std::size_t ground = 0, ground_up = 0, sphere = 0, sphere_out = 0;
  const Eigen::Vector3f centre(-0.9f, 0.8f, 0.9f);
  for (const auto& p : data.cloud->points) {
    const Eigen::Vector3f x = p.getVector3fMap(), n = p.getNormalVector3fMap();
    if (std::abs(x.z()) < 0.02f && (x - Eigen::Vector3f(0.8f, -0.6f, 0)).head<2>().norm() > 0.6f) {
      ++ground;
      ground_up += n.z() > 0.95f ? 1 : 0;
    }
    if (std::abs((x - centre).norm() - 0.5f) < 0.02f) {
      ++sphere;
      sphere_out += n.dot(x - centre) > 0 ? 1 : 0;
    }
  }
  EXPECT_GT(ground, 15000u);
  EXPECT_GE(ground_up, ground * 995 / 1000);
  EXPECT_GT(sphere, 7000u);
  EXPECT_EQ(sphere_out, sphere);
}

// Issue 38: orientation 'sensor' (the demo config's) follows PCL's convention, normals facing the
// input's sensor_origin_ (a PCD's VIEWPOINT); an input without a sensor pose falls back to the
// viewpoint, and the report says which. A 21 × 21 grid on the plane z = 0 with the sensor below
// it at (0.3, −0.2, −3): every normal is −z; the same points as a PLY face the viewpoint above.
TEST(Cli, SensorOrientationFacesThePcdsViewpointElseTheViewpoint) {
  const std::string dir = scratchDir("sensor_orientation");
  fs::create_directories(dir);
  std::string rows;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j)
      rows += std::to_string(0.05 * i) + " " + std::to_string(0.05 * j + 0.001 * (i % 3)) + " 0\n";
  {
    std::ofstream pcd(dir + "/plane.pcd");
    pcd << "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 441\nHEIGHT "
           "1\nVIEWPOINT 0.3 -0.2 -3 1 0 0 0\nPOINTS 441\nDATA ascii\n"
        << rows;
    std::ofstream ply(dir + "/plane.ply");
    ply << "ply\nformat ascii 1.0\nelement vertex 441\nproperty float x\nproperty float "
           "y\nproperty float z\nend_header\n"
        << rows;
  }
  for (const std::string ext : {"pcd", "ply"}) {
    const std::string out = dir + "/out_" + ext;
    const CliResult r =
        runSlipfit("run configs/normals_demo.yaml --set input.path=" + dir + "/plane." + ext +
                   " --set normals.orientation=sensor --set output.dir=" + out);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_THAT(r.out,
                HasSubstr(ext == "pcd" ? "orientation sensor (towards the input's sensor at (0.3, "
                                         "-0.2, -3))"
                                       : "orientation sensor (the input has no sensor pose: "
                                         "towards the viewpoint (0, 0, 10))"));
    const auto data = pipeline::readCloud(out + "/cloud.ply", pipeline::NanPolicy::error);
    ASSERT_EQ(data.size(), 441u);
    const float sign = ext == "pcd" ? -1.0f : 1.0f;
    for (const auto& p : data.cloud->points)
      ASSERT_GT(sign * p.normal_z, 0.999f)
          << ext << ": the point " << p.getVector3fMap().transpose();
  }
}

TEST(Cli, SameOutputForSameInputAndAnyThreadCount) {
  const std::string a = scratchDir("det_a"), b = scratchDir("det_b");
  ASSERT_EQ(
      runSlipfit("run configs/adaptive_normals.yaml --quiet --set threads=1 --set output.dir=" + a)
          .code,
      0);
  ASSERT_EQ(
      runSlipfit("run configs/adaptive_normals.yaml --quiet --set threads=2 --set output.dir=" + b)
          .code,
      0);
  EXPECT_EQ(slurp(a + "/cloud.ply"), slurp(b + "/cloud.ply"));
  EXPECT_GT(slurp(a + "/cloud.ply").size(), 6000u * 12);
}

TEST(Cli, QuietPrintsNothingAndSetOverrides) {
  const std::string out = scratchDir("quiet");
  CliResult r = runSlipfit("run configs/normals_demo.yaml --quiet --set output.dir=" + out);
  EXPECT_EQ(r.code, 0);
  EXPECT_EQ(r.out + r.err, "");
  r = runSlipfit(
      "run configs/normals_demo.yaml --set neighborhoods.k=8 --set output.format=ascii --set "
      "output.dir=" +
      out);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("sizes 8..8"));
  EXPECT_THAT(slurp(out + "/cloud.ply").substr(0, 30), HasSubstr("format ascii"));
}

TEST(Cli, StagesDescribeValidate) {
  CliResult r = runSlipfit("stages");
  EXPECT_EQ(r.code, 0);
  EXPECT_THAT(r.out, HasSubstr("neighborhood_selection"));
  EXPECT_THAT(r.out, HasSubstr("normal_estimation"));

  r = runSlipfit("describe neighborhood_selection");
  EXPECT_EQ(r.code, 0);
  EXPECT_THAT(r.out, HasSubstr("  k  (int, points)  default: 16  range: [3, 10000]"));
  EXPECT_THAT(
      r.out,
      HasSubstr("  mode  (enum)  default: knn  range: one of knn, radius, hybrid, adaptive"));
  EXPECT_THAT(r.out, HasSubstr("consumes: points; produces: neighborhoods"));
  r = runSlipfit("describe input");
  EXPECT_THAT(r.out, HasSubstr("  path  (string)  default: required"));
  r = runSlipfit("describe tiling");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("  size  (float, units)  default: 0  range: [0, inf)"));
  EXPECT_THAT(r.out, HasSubstr("  workdir  (string"));
  for (const char* name : {"run", "threads", "seed"}) {
    r = runSlipfit(std::string("describe ") + name);
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_THAT(r.out, HasSubstr("  threads  (int)  default: 0  range: [0, 1024]")) << name;
    EXPECT_THAT(r.out, HasSubstr("  seed  (")) << name;
  }

  r = runSlipfit("validate configs/normals_demo.yaml");
  EXPECT_EQ(r.code, 0);
  EXPECT_EQ(r.out, "configs/normals_demo.yaml: valid, 3 stages\n");
  r = runSlipfit("validate configs/sample_scan.yaml");
  EXPECT_EQ(r.out, "configs/sample_scan.yaml: valid, 1 stage\n");
  // Issue 38: a stage that needs normals the input does not have is refused by validate with
  // the line run refuses it with (it said "valid" and run then exited 1).
  r = runSlipfit("validate configs/classify.yaml --set input.path=sample_clouds/scene.ply");
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.err,
            "slipfit: error: configs/classify.yaml: stage 'slippage' (slippage_classification) "
            "needs normals: the input has none and no earlier stage produces them\n");
  EXPECT_EQ(r.out, "");
}

struct ErrorCase {
  const char* name;
  std::string config;  // YAML text; "{in}" is replaced by the input path
  std::string input;   // contents of the input cloud file ("" = no file)
  int code;
  std::string message;  // expected part of the one error line
};

void PrintTo(const ErrorCase& c, std::ostream* os) {
  *os << c.name;
}

class CliErrors : public ::testing::TestWithParam<ErrorCase> {};

const char* kAsciiHeader3 =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float "
    "z\nend_header\n";
const std::string kTwoStages =
    "stages:\n  - type: neighborhood_selection\n  - type: normal_estimation\n";

TEST_P(CliErrors, OneLineNonZeroExitNoOutput) {
  const ErrorCase& c = GetParam();
  const std::string out = scratchDir(std::string("err_") + c.name);
  std::string input = "/nonexistent/input.ply";
  if (!c.input.empty())
    input = scratchFile(std::string(c.name) + ".ply", c.input);
  std::string yaml = c.config;
  const auto at = yaml.find("{in}");
  if (at != std::string::npos)
    yaml.replace(at, 4, input);
  const std::string cfg = scratchFile(std::string(c.name) + ".yaml", yaml);
  // Cases that name their own output dir keep it.
  const bool own_output = yaml.find("output:") != std::string::npos;
  const CliResult r =
      runSlipfit("run '" + cfg + "'" + (own_output ? "" : " --set output.dir=" + out));
  EXPECT_EQ(r.code, c.code) << r.err;
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_THAT(r.err, StartsWith("slipfit: error: "));
  EXPECT_THAT(r.err, HasSubstr(c.message));
  EXPECT_EQ(filesIn(out), 0u) << "a failed run left files in " << out;
}

std::string points(int n) {
  std::string s = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(n) +
                  "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  for (int i = 0; i < n; ++i)
    s += std::to_string(i % 10) + " " + std::to_string(i / 10) + " " + std::to_string((i * 7) % 3) +
         "\n";
  return s;
}

INSTANTIATE_TEST_SUITE_P(
    Catalogue, CliErrors,
    ::testing::Values(
        ErrorCase{
            "unknown_stage", "input: {path: x.ply}\nstages:\n  - type: normals\n", "", 2,
            ":3:11: unknown stage type 'normals'; known stages: " + pipeline::knownStagesText()},
        ErrorCase{"unknown_key",
                  "input: {path: x.ply}\nstages:\n  - type: normal_estimation\n    orientaton: "
                  "consistent\n",
                  "", 2,
                  ":4:5: stage 'normal_estimation' (normal_estimation): unknown key 'orientaton'; "
                  "valid keys: k, radius"},
        ErrorCase{"bad_value",
                  "input: {path: x.ply}\nstages:\n  - type: neighborhood_selection\n    k: -4\n",
                  "", 2,
                  ":4:8: stage 'neighborhood_selection' (neighborhood_selection): key 'k': must be "
                  "in [3, 10000], got -4"},
        ErrorCase{"missing_file", "input: {path: {in}}\n" + kTwoStages, "", 1,
                  "input '/nonexistent/input.ply': no such file"},
        ErrorCase{"not_a_ply", "input: {path: {in}}\n" + kTwoStages, "x", 1,
                  "not a PLY file (it does not start with 'ply')"},
        ErrorCase{"empty_cloud", "input: {path: {in}}\n" + kTwoStages,
                  "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float "
                  "y\nproperty float z\nend_header\n",
                  1, "the cloud is empty (0 points)"},
        ErrorCase{"nan", "input: {path: {in}, nan: error}\n" + kTwoStages,
                  std::string(kAsciiHeader3) + "0 0 0\n1 nan 1\n2 2 2\n", 1,
                  "point 1 has a non-finite coordinate"},
        ErrorCase{
            "needs_normals",
            "input: {path: {in}}\nstages:\n  - type: normal_estimation\n    orientation: "
            "reference\n",
            points(50), 1,
            "stage 'normal_estimation' (normal_estimation) needs normals: the input has none"},
        ErrorCase{"stage_fails_late",
                  "input: {path: {in}}\nstages:\n  - type: neighborhood_selection\n  - type: "
                  "normal_estimation\n"
                  "    use_shared: false\n    radius: 0.01\n    failed: error\n",
                  points(50), 1,
                  "stage 'normal_estimation' (normal_estimation): 50 points have no normal"},
        ErrorCase{"unwritable_output",
                  "input: {path: {in}}\n" + kTwoStages + "output: {dir: /proc/slipfit}\n",
                  points(50), 1, "cannot create the directory"}),
    [](const auto& info) { return std::string(info.param.name); });

// Issue 15: a FIFO given as the config blocked forever (`timeout` turns a hang into exit 124).
// Issue 38: over every shipped config that reads an input, on a cloud without normals and one
// with them, validate refuses exactly what run refuses for a missing field, with run's line; what
// validate accepts runs to its end.
TEST(Cli, ValidateRefusesWhatRunRefusesForEveryShippedConfig) {
  std::size_t refused = 0, accepted = 0;
  for (const auto& entry : fs::directory_iterator(std::string(kSourceDir) + "/configs")) {
    const std::string config = "configs/" + entry.path().filename().string();
    if (slurp(entry.path().string()).find("\ninput:") == std::string::npos)
      continue;  // a generator: no input to check against
    for (const char* input : {"sample_clouds/scene.ply", "sample_clouds/torus_normals.ply"}) {
      const std::string set = std::string(" --set input.path=") + input;
      const CliResult v = runSlipfit("validate " + config + set);
      const CliResult r = runSlipfit("run " + config + set + " --quiet --set output.dir=" +
                                     scratchDir("contract_" + std::to_string(refused + accepted)));
      EXPECT_EQ(v.code, r.code) << config << " on " << input << ": validate said " << v.out << v.err
                                << ", run " << r.err;
      if (v.code != 0) {
        EXPECT_EQ(v.err, r.err) << config << " on " << input;
        ++refused;
      } else {
        ++accepted;
      }
    }
  }
  // The shipped configs include ones that need input normals (classify) and many that do not.
  EXPECT_GE(refused, 1u);
  EXPECT_GE(accepted, 8u);
}

TEST(Cli, AFifoAsTheConfigIsRefusedWithoutBlocking) {
  const std::string fifo = scratchDir("config_fifo.yaml");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const char* command : {"validate", "run"}) {
    const CliResult r = runSlipfit(std::string(command) + " '" + fifo + "'", "", "timeout 20");
    EXPECT_EQ(r.code, 2) << command << ": " << r.err;
    EXPECT_THAT(r.err, HasSubstr("config_fifo.yaml': not a regular file (a FIFO, socket or device "
                                 "would block or never end)"));
  }
  std::filesystem::remove(fifo);
}

TEST(Cli, UsageErrorsExitTwo) {
  EXPECT_EQ(runSlipfit("").code, 2);
  EXPECT_EQ(runSlipfit("frobnicate").code, 2);
  EXPECT_EQ(runSlipfit("run").code, 2);
  EXPECT_EQ(runSlipfit("run configs/normals_demo.yaml --sett x=1").code, 2);
  CliResult r = runSlipfit("describe normal_estimaton");
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("unknown stage 'normal_estimaton'; known stages: " +
                               pipeline::knownStagesText()));
  r = runSlipfit("run /nonexistent.yaml");
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("config '/nonexistent.yaml': no such file"));
  EXPECT_EQ(runSlipfit("--help").code, 0);
}

}  // namespace
}  // namespace slipfit::testing

namespace slipfit::testing {
namespace {

// The version printed is the one project(VERSION) declares in the top-level CMakeLists.txt.
TEST(Cli, VersionComesFromTheProject) {
  const std::string cmake = slurp(std::string(kSourceDir) + "/CMakeLists.txt");
  const auto at = cmake.find("project(slipfit VERSION ");
  ASSERT_NE(at, std::string::npos);
  const auto begin = at + std::string("project(slipfit VERSION ").size();
  const std::string version = cmake.substr(begin, cmake.find(' ', begin) - begin);
  const CliResult r = runSlipfit("--version");
  EXPECT_EQ(r.code, 0);
  EXPECT_EQ(r.out, "slipfit " + version + "\n");
}

// docs/stages.md is generated from the option declarations; it must match what describe prints.
TEST(Cli, StageDocsAreUpToDate) {
  const std::string docs = slurp(std::string(kSourceDir) + "/docs/stages.md");
  std::vector<std::string> names = {"input", "output", "tiling", "run"};
  std::istringstream stages(runSlipfit("stages").out);
  for (std::string line; std::getline(stages, line);)
    names.push_back(line.substr(0, line.find(' ')));
  ASSERT_GE(names.size(), 4u);
  for (const auto& name : names) {
    const CliResult r = runSlipfit("describe " + name);
    ASSERT_EQ(r.code, 0);
    EXPECT_THAT(docs, HasSubstr("## " + name + "\n\n```\n" + r.out + "```\n"))
        << "docs/stages.md is stale for '" << name << "': run docs/generate_stages.sh";
  }
}

}  // namespace
}  // namespace slipfit::testing
