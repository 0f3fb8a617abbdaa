#include "slipfit/pipeline/options.h"
#include "slipfit/pipeline/errors.h"

#include "slipfit/fitting/primitives.h"
#include "slipfit/neighborhoods/neighborhood_selection.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

namespace slipfit::pipeline {
namespace {

void parse(const OptionSet& set, const std::string& name, const std::string& yaml) {
  set.find(name)->parse(YAML::Load(yaml));
}

TEST(Options, IntegersAreCheckedForTypeAndRange) {
  int k = 16;
  OptionSet set;
  set.add("k", k, "help").range(3, 100);
  EXPECT_EQ(set.find("k")->defaultText(), "16");
  parse(set, "k", "30");
  EXPECT_EQ(k, 30);
  EXPECT_THROW(parse(set, "k", "2"), OptionValueError);
  EXPECT_THROW(parse(set, "k", "1.5"), OptionValueError);
  EXPECT_THROW(parse(set, "k", "abc"), OptionValueError);
  EXPECT_THROW(parse(set, "k", "[1, 2]"), OptionValueError);
  EXPECT_EQ(k, 30) << "a rejected value must not be stored";
  try {
    parse(set, "k", "101");
  } catch (const OptionValueError& e) {
    EXPECT_STREQ(e.what(), "must be in [3, 100], got 101");
  }
}

TEST(Options, FloatsRejectNaNAndOpenBounds) {
  std::optional<double> r;
  OptionSet set;
  set.add("radius", r, "help").above(0);
  EXPECT_EQ(set.find("radius")->defaultText(), "unset");
  EXPECT_EQ(set.find("radius")->rangeText(), "(0, inf)");
  EXPECT_THROW(parse(set, "radius", "0"), OptionValueError);
  EXPECT_THROW(parse(set, "radius", ".nan"), OptionValueError);
  EXPECT_THROW(parse(set, "radius", "nan"), OptionValueError);
  EXPECT_THROW(parse(set, "radius", "-1e-3"), OptionValueError);
  parse(set, "radius", "2.5e-2");
  EXPECT_DOUBLE_EQ(*r, 0.025);
}

TEST(Options, AnOpenUpperBoundExcludesItsValue) {
  double angle = 0.0;
  OptionSet set;
  set.add("angle", angle, "help").atLeast(0).below(360);
  EXPECT_EQ(set.find("angle")->rangeText(), "[0, 360)");
  EXPECT_THROW(parse(set, "angle", "360"), OptionValueError);
  parse(set, "angle", "359.5");
  EXPECT_DOUBLE_EQ(angle, 359.5);
  double top = 1.0;
  set.add("top", top, "help").above(0).atMost(360);
  EXPECT_EQ(set.find("top")->rangeText(), "(0, 360]");
  EXPECT_THROW(parse(set, "top", "0"), OptionValueError);
  parse(set, "top", "360");
  EXPECT_DOUBLE_EQ(top, 360.0);
}

TEST(Options, AnEnumTheStageMayChooseIsUnsetByItsAutomaticName) {
  std::optional<PrimitiveType> type;
  OptionSet set;
  set.add("primitive", type, "auto", kPrimitiveTypeNames, "help");
  EXPECT_EQ(set.find("primitive")->defaultText(), "auto");
  EXPECT_EQ(set.find("primitive")->rangeText(),
            "one of auto, plane, sphere, cylinder, cone, torus");
  parse(set, "primitive", "cone");
  EXPECT_EQ(type, PrimitiveType::cone);
  parse(set, "primitive", "auto");
  EXPECT_FALSE(type.has_value());
  EXPECT_THROW(parse(set, "primitive", "cylindre"), OptionValueError);
  EXPECT_FALSE(type.has_value()) << "a rejected value must not be stored";
}

TEST(Options, EnumsUseTheirNameTable) {
  NeighborhoodMode mode = NeighborhoodMode::knn;
  OptionSet set;
  set.add("mode", mode, kNeighborhoodModeNames, "help");
  EXPECT_EQ(set.find("mode")->defaultText(), "knn");
  EXPECT_EQ(set.find("mode")->rangeText(), "one of knn, radius, hybrid, adaptive");
  parse(set, "mode", "adaptive");
  EXPECT_EQ(mode, NeighborhoodMode::adaptive);
  try {
    parse(set, "mode", "knnn");
    FAIL();
  } catch (const OptionValueError& e) {
    EXPECT_STREQ(e.what(), "'knnn' is not one of knn, radius, hybrid, adaptive");
  }
}

TEST(Options, BoolsStringsAndVectors) {
  bool b = false;
  std::string s = "x";
  Eigen::Vector3f v = Eigen::Vector3f::Zero();
  std::uint64_t seed = 0;
  OptionSet set;
  set.add("b", b, "");
  set.add("s", s, "");
  set.add("v", v, "");
  set.add("seed", seed, "");
  parse(set, "b", "yes");
  EXPECT_TRUE(b);
  EXPECT_THROW(parse(set, "b", "maybe"), OptionValueError);
  EXPECT_THROW(parse(set, "s", "''"), OptionValueError);
  parse(set, "v", "[1, 2.5, -3]");
  EXPECT_EQ(v, Eigen::Vector3f(1, 2.5f, -3));
  EXPECT_THROW(parse(set, "v", "[1, 2]"), OptionValueError);
  EXPECT_THROW(parse(set, "v", "[1, 2, x]"), OptionValueError);
  EXPECT_THROW(parse(set, "seed", "-4"), OptionValueError);
  parse(set, "seed", "18446744073709551615");
  EXPECT_EQ(seed, 18446744073709551615ull);
  EXPECT_EQ(set.namesText(), "b, s, v, seed");
  EXPECT_EQ(set.find("nope"), nullptr);
}

}  // namespace
}  // namespace slipfit::pipeline
