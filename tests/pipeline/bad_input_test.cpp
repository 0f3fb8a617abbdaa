// The bad-input catalogue (tests/bad_inputs/catalogue.yaml): each case gives one error line with
// the expected text and exit code, and leaves no file behind.
#include "run_cli.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iostream>

namespace slipfit::testing {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

// Peak memory is measured with /usr/bin/time (installed by .ci/setup) except under the
// sanitizers, whose shadow memory and quarantine are not the program's.
#ifdef SLIPFIT_TESTS_SANITIZED
constexpr bool kMeasureMemory = false;
#else
constexpr bool kMeasureMemory = true;
#endif

struct BadInput {
  std::string name, config, prefix, message, stdout_text;
  bool validate = false;  // `slipfit validate` must fail the same way, before anything runs
  int exit = 1;
};

void PrintTo(const BadInput& c, std::ostream* os) {
  *os << c.name;
}

std::vector<BadInput> catalogue() {
  std::vector<BadInput> cases;
  const YAML::Node all =
      YAML::LoadFile(std::string(kSourceDir) + "/tests/bad_inputs/catalogue.yaml");
  for (std::size_t i = 0; i < all.size(); ++i) {
    const YAML::Node c = all[i];
    BadInput b;
    b.name = c["name"].as<std::string>();
    b.config = c["config"].as<std::string>();
    b.prefix = c["prefix"] ? c["prefix"].as<std::string>() : "";
    b.validate = c["validate"] && c["validate"].as<bool>();
    b.exit = c["exit"].as<int>();
    b.message = c["message"] ? c["message"].as<std::string>() : "";
    b.stdout_text = c["stdout"] ? c["stdout"].as<std::string>() : "";
    cases.push_back(b);
  }
  return cases;
}

class BadInputs : public ::testing::TestWithParam<BadInput> {};

TEST_P(BadInputs, OneLineExitCodeNoOutput) {
  const BadInput& c = GetParam();
  std::string yaml = c.config;
  const std::string dir = std::string(kSourceDir) + "/tests/bad_inputs";
  for (auto at = yaml.find("{dir}"); at != std::string::npos; at = yaml.find("{dir}"))
    yaml.replace(at, 5, dir);
  std::string prefix = c.prefix;
  for (auto at = prefix.find("{dir}"); at != std::string::npos; at = prefix.find("{dir}"))
    prefix.replace(at, 5, dir);
  std::string message = c.message;
  for (auto at = message.find("{dir}"); at != std::string::npos; at = message.find("{dir}"))
    message.replace(at, 5, dir);
  const std::string out = scratchDir("bad_" + c.name);
  const bool own_output =
      yaml.find("dir: /") != std::string::npos && yaml.find("output:") != std::string::npos;
  const std::string cfg = scratchFile("bad_" + c.name + ".yaml", yaml);
  const std::string peak_file = scratchDir("bad_" + c.name + ".peak");
  const CliResult r =
      runSlipfit("run '" + cfg + "'" + (own_output ? "" : " --set output.dir=" + out), prefix,
                 kMeasureMemory ? "/usr/bin/time -f %M -o '" + peak_file + "'" : "");
  if (kMeasureMemory) {
    // Issue 15's bound: peak memory under 64 × the input file's size + 200 MB.
    std::uintmax_t file_bytes = 0;
    try {
      const YAML::Node node = YAML::Load(yaml);
      std::error_code ec;
      if (node.IsMap() && node["input"].IsMap() && node["input"]["path"])
        file_bytes = std::filesystem::file_size(node["input"]["path"].as<std::string>(), ec);
      if (ec)
        file_bytes = 0;
    } catch (const YAML::Exception&) {
      // a case whose config is broken on purpose: no input read
    }
    std::ifstream peak(peak_file);
    double peak_kb = -1;
    for (std::string line; std::getline(peak, line);)
      if (!line.empty() && std::isdigit(static_cast<unsigned char>(line[0])))
        peak_kb = std::stod(line);  // the last line: "Command exited ..." comes first
    ASSERT_GE(peak_kb, 0) << "no peak memory measured";
    std::cout << c.name << ": peak " << peak_kb / 1024.0 << " MB for an input of " << file_bytes
              << " bytes\n";
    EXPECT_LE(peak_kb * 1024, 64.0 * static_cast<double>(file_bytes) + 200e6)
        << "input of " << file_bytes << " bytes";
  }
  EXPECT_EQ(r.code, c.exit) << r.err;
  if (c.exit == 0) {
    EXPECT_EQ(r.err, "");
    EXPECT_THAT(r.out, HasSubstr(c.stdout_text));
    return;
  }
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_THAT(r.err, StartsWith("slipfit: error: "));
  EXPECT_THAT(r.err, HasSubstr(message));
  EXPECT_FALSE(std::filesystem::exists(out) && !std::filesystem::is_empty(out))
      << "a failed run left files in " << out;
  if (c.validate) {
    const CliResult v =
        runSlipfit("validate '" + cfg + "'" + (own_output ? "" : " --set output.dir=" + out));
    EXPECT_EQ(v.code, c.exit) << v.err;
    EXPECT_EQ(std::count(v.err.begin(), v.err.end(), '\n'), 1) << v.err;
    EXPECT_THAT(v.err, HasSubstr(message));
  }
}

INSTANTIATE_TEST_SUITE_P(Catalogue, BadInputs, ::testing::ValuesIn(catalogue()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace slipfit::testing
