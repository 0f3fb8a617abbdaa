// Each stage's declared option ranges against its library's own validation (issue 16): every
// value an option accepts — each numeric option set to either end of its declared range, the
// others at their defaults — must pass the stage's prepare(), which hands the values to the
// library's validate(). A library check stricter than the declared range (a declared [0, 1] over
// a library's (0, 1]) fails here.
#include "slipfit/pipeline/errors.h"
#include "slipfit/pipeline/options.h"
#include "slipfit/pipeline/registry.h"

#include "slipfit/core/exceptions.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace slipfit::pipeline {
namespace {

/// The values at the ends of \a option's range that it accepts.
std::vector<double> acceptedEnds(const Option& option) {
  std::vector<double> ends;
  const bool integral = option.type() == "int";
  if (const auto lo = option.low()) {
    double v = *lo;
    if (option.lowOpen())
      v = integral ? std::floor(v) + 1.0 : v + 1e-9 * std::max(1.0, std::abs(v));
    ends.push_back(v);
  }
  if (const auto hi = option.high()) {
    double v = *hi;
    if (option.highOpen())
      v = integral ? std::ceil(v) - 1.0 : v - 1e-9 * std::max(1.0, std::abs(v));
    ends.push_back(v);
  }
  return ends;
}

std::string text(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", v);
  return buffer;
}

using Settings = std::vector<std::pair<std::string, std::string>>;

// Stages whose defaults alone do not make a valid stage: a value must be given (crop needs its
// limits). Their ranges are checked with those values set.
const std::map<std::string, Settings> kRequired = {
    {"crop", {{"field", "z"}, {"min", "-1"}, {"max", "1"}}},
};

// Options bound to another by the library (a relation, not a range): the end of one's range is
// checked with the other set where the relation holds.
const std::map<std::string, Settings> kCompanions = {
    {"torus_sampling.major_radius", {{"minor_radius", "1e-10"}}},
    {"torus_sampling.alpha_min", {{"alpha_max", "360"}}},
    {"torus_sampling.alpha_max", {{"alpha_min", "0"}}},
    {"torus_sampling.beta_min", {{"beta_max", "360"}}},
    {"torus_sampling.beta_max", {{"beta_min", "0"}}},
    {"primitive_sampling.angle_min", {{"angle_max", "360"}}},
    {"primitive_sampling.angle_max", {{"angle_min", "0"}}},
    {"outlier_removal.radius", {{"method", "radius"}}},
    {"neighborhood_selection.k_min", {{"k_max", "10000"}}},
    {"neighborhood_selection.k_max", {{"k_min", "3"}}},
    {"scan_sampling.distance_min", {{"distance_max", "1e300"}}},
    {"scan_sampling.distance_max", {{"distance_min", "1e-300"}}},
};

TEST(OptionRanges, EveryValueAStageDeclaresPassesItsLibrarysValidation) {
  std::size_t checked = 0;
  for (const StageInfo& info : stageRegistry()) {
    OptionSet declared;
    auto probe = info.make();
    probe->declare(declared);
    for (const auto& option : declared.all()) {
      for (const double value : acceptedEnds(*option)) {
        auto stage = info.make();
        OptionSet set;
        stage->declare(set);
        const std::string key = std::string(info.name) + "." + option->name();
        for (const auto* table : {&kRequired, &kCompanions}) {
          const auto given = table->find(table == &kRequired ? std::string(info.name) : key);
          if (given != table->end())
            for (const auto& [name, yaml] : given->second)
              if (name != option->name())
                set.find(name)->parse(YAML::Load(yaml));
        }
        const std::string where =
            std::string(info.name) + "." + option->name() + " = " + text(value);
        ASSERT_NO_THROW(set.find(option->name())->parse(YAML::Load(text(value)))) << where;
        try {
          stage->prepare();
        } catch (const std::exception& e) {
          ADD_FAILURE() << where << " is in the declared range " << option->rangeText()
                        << " but the stage refuses it: " << e.what();
        }
        ++checked;
      }
    }
  }
  // Every stage's numeric options: a registry that declared none would pass vacuously.
  EXPECT_GT(checked, 40u);
}

}  // namespace
}  // namespace slipfit::pipeline
