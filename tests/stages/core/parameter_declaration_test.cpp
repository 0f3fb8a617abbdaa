// Each library parameters struct declares its fields once (parameter_declaration.h); its
// validate() must enforce exactly those ranges (issue 16). For every declared bound of every
// struct, a value just beyond it is refused with a message naming the field, and the struct's
// defaults pass. The pipeline's options bind to the same declarations, and
// tests/pipeline/option_ranges_test.cpp checks that the values at the bounds pass.

#include "slipfit/core/parameter_declaration.h"
#include "slipfit/filters/point_filters.h"
#include "slipfit/filters/subsampling.h"
#include "slipfit/fitting/labelled_fit.h"
#include "slipfit/fitting/robust_fit.h"
#include "slipfit/fitting/weighted_fit.h"
#include "slipfit/neighborhoods/neighborhood_selection.h"
#include "slipfit/neighborhoods/normal_estimation.h"
#include "slipfit/render/splat_renderer.h"
#include "slipfit/sampling/labelled_scene.h"
#include "slipfit/sampling/motion_surface_sampler.h"
#include "slipfit/sampling/primitive_sampler.h"
#include "slipfit/sampling/torus_sampler.h"
#include "slipfit/segmentation/segmentation.h"
#include "slipfit/slippage/slippage.h"
#include "slipfit/surfaces/torus_mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

namespace slipfit {
namespace {

template <typename T>
constexpr bool kNumeric = std::is_arithmetic_v<T> && !std::is_same_v<T, bool>;

/// Sets \a field (number or optional number) to \a value; false when it holds no number.
template <typename T>
bool assign(T& field, double value) {
  if constexpr (detail::IsOptional<T>::value) {
    typename T::value_type inner{};
    if (!assign(inner, value))
      return false;
    field = inner;
    return true;
  } else if constexpr (kNumeric<T>) {
    field = static_cast<T>(value);
    return true;
  } else {
    return false;
  }
}

template <typename T>
constexpr bool isIntegral() {
  if constexpr (detail::IsOptional<T>::value)
    return std::is_integral_v<typename T::value_type>;
  else
    return std::is_integral_v<T>;
}

/// The field values (in the field's unit) just outside \a d's bounds.
std::vector<double> beyond(const ParameterDeclaration& d, bool integral) {
  std::vector<double> v;
  const auto step = [&](double x) { return integral ? 1.0 : 1e-6 * std::max(1.0, std::abs(x)); };
  if (d.range.low) {
    const double lo = *d.range.low;
    const double out = d.range.low_open ? (integral ? std::floor(lo) : lo) : lo - step(lo);
    // An unsigned count cannot hold a negative value: its range starts at 0 anyway.
    if (!(integral && out < 0))
      v.push_back(out * d.scale);
  }
  if (d.range.high) {
    const double hi = *d.range.high;
    v.push_back((d.range.high_open ? (integral ? std::ceil(hi) : hi) : hi + step(hi)) * d.scale);
  }
  return v;
}

/// \a base: valid parameters (the defaults, or for a type without a complete default, the
/// smallest completion); each bound is crossed from there.
template <typename Parameters>
std::size_t expectEveryBoundEnforced(const char* name, const Parameters& base = Parameters{}) {
  EXPECT_NO_THROW(base.validate()) << name << ": the base parameters";
  std::size_t checked = 0;
  Parameters names_only = base;
  std::size_t index = 0;
  Parameters::forEachParameter(names_only, [&](auto& field, const ParameterDeclaration& d,
                                               const auto&...) {
    using T = std::decay_t<decltype(field)>;
    const std::size_t target = index++;
    for (const double value : beyond(d, isIntegral<T>())) {
      Parameters p = base;
      std::size_t k = 0;
      bool set = false;
      Parameters::forEachParameter(p, [&](auto& f, const ParameterDeclaration&, const auto&...) {
        if (k++ == target)
          set = assign(f, value);
      });
      if (!set)
        continue;
      ++checked;
      try {
        p.validate();
        ADD_FAILURE() << name << ": " << d.name << " = " << value << " was accepted, outside "
                      << d.range.text();
      } catch (const InvalidParameterError& e) {
        EXPECT_NE(std::string(e.what()).find(std::string(d.name)), std::string::npos) << e.what();
      }
    }
  });
  return checked;
}

TEST(ParameterDeclarations, EveryDeclaredBoundIsEnforcedByTheLibrarysValidate) {
  std::size_t checked = 0;
  checked += expectEveryBoundEnforced<NeighborhoodParameters>("NeighborhoodParameters");
  checked += expectEveryBoundEnforced<NormalParameters>("NormalParameters");
  checked += expectEveryBoundEnforced<SlippageOptions>("SlippageOptions");
  checked += expectEveryBoundEnforced<FitOptions>("FitOptions");
  checked += expectEveryBoundEnforced<RobustOptions>("RobustOptions");
  checked += expectEveryBoundEnforced<SegmentationParameters>("SegmentationParameters");
  checked += expectEveryBoundEnforced<TorusSamplingParameters>("TorusSamplingParameters");
  checked += expectEveryBoundEnforced<MotionSurfaceParameters>("MotionSurfaceParameters");
  checked += expectEveryBoundEnforced<SubsampleParameters>("SubsampleParameters");
  checked += expectEveryBoundEnforced<PrimitiveDescription>("PrimitiveDescription");
  checked += expectEveryBoundEnforced<PrimitiveSamplingParameters>("PrimitiveSamplingParameters");
  checked += expectEveryBoundEnforced<LabelledSceneParameters>("LabelledSceneParameters");
  checked += expectEveryBoundEnforced<RenderParameters>("RenderParameters");
  VoxelGridParameters voxels;
  voxels.leaf = 1.0;  // required: no default
  checked += expectEveryBoundEnforced<VoxelGridParameters>("VoxelGridParameters", voxels);
  checked += expectEveryBoundEnforced<OutlierRemovalParameters>("OutlierRemovalParameters");
  checked += expectEveryBoundEnforced<LabelledFitParameters>("LabelledFitParameters");
  checked += expectEveryBoundEnforced<TorusMeshParameters>("TorusMeshParameters");
  // 2 bounds each: k, max_neighbors, k_min, k_max, k_step (10) and radius (1); normals k (2),
  // radius (1); slippage 4 × 2; max_iterations (2); robust threshold (1), ransac_iterations (2);
  // segmentation distance (1), max_angle (2), min_points (2), merge_factor (2); torus sampling
  // major and minor radius (1 each), noise and normal_noise (1 each), spin, points, the four
  // coverage angles and outliers (2 each); motion surface radius, length and noise (1 each),
  // points (2); subsample points (2), leaf (1); primitive radius, major and minor radius (1
  // each), half_angle (2); primitive sampling extent, extent_min, noise, normal_noise (1 each),
  // the two coverage angles, cap, points, outliers and flips (2 each); scene size (1), shapes,
  // points, noise and outliers (2 each); render width and height (2 each); voxel leaf (1);
  // outlier removal k, stddev and min_neighbors (2 each), radius (1); labelled fit
  // max_iterations, min_points, ransac_iterations (2 each), inlier_distance, threshold (1 each);
  // torus mesh alpha and beta resolutions (2 each).
  EXPECT_EQ(checked,
            11u + 3u + 8u + 2u + 3u + 7u + 18u + 5u + 3u + 5u + 16u + 9u + 4u + 1u + 7u + 8u + 4u);
}

// The message names the field, the range in the user's unit and the value in it: a max_angle of
// 100° (held in radians) is reported in degrees.
TEST(ParameterDeclarations, MessageNamesTheFieldRangeAndValueInTheUsersUnit) {
  SegmentationParameters p;
  p.max_angle = 100.0 * kDegree;
  try {
    p.validate();
    FAIL() << "max_angle 100° accepted";
  } catch (const InvalidParameterError& e) {
    EXPECT_STREQ(e.what(), "segmentation: max_angle must be in (0, 90] deg, got 100 deg");
  }
  // The bound itself, reached from degrees, passes: 90 × kDegree is not rounded past it.
  p.max_angle = 90.0 * kDegree;
  EXPECT_NO_THROW(p.validate());
}

// The PCL-style classes take their parameters as PCL's setters do and check them once, when the
// work runs: the message names the field.
template <typename Run>
void expectRefusedWhenRun(Run run, const std::string& field) {
  try {
    run();
    ADD_FAILURE() << field << " out of range was accepted";
  } catch (const InvalidParameterError& e) {
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

TEST(ParameterDeclarations, PclStyleClassesCheckTheirParametersWhenTheyRun) {
  const auto cloud = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  NeighborhoodParameters hood;
  hood.k = 2;
  NeighborhoodSelection<pcl::PointNormal> selection;
  EXPECT_NO_THROW(selection.setParameters(hood));
  selection.setInputCloud(cloud);
  Neighborhoods neighborhoods;
  expectRefusedWhenRun([&] { selection.compute(neighborhoods); }, "k");

  NormalParameters normal;
  normal.k = 1;
  OrientedNormalEstimation<pcl::PointNormal, pcl::Normal> estimation;
  EXPECT_NO_THROW(estimation.setParameters(normal));
  estimation.setInputCloud(cloud);
  pcl::PointCloud<pcl::Normal> normals;
  expectRefusedWhenRun([&] { estimation.compute(normals); }, "k");

  TorusSamplingParameters torus;
  torus.points = 0;
  TorusSampler sampler;
  EXPECT_NO_THROW(sampler.setParameters(torus));
  pcl::PointCloud<pcl::PointNormal> samples;
  expectRefusedWhenRun([&] { sampler.sample(samples); }, "points");
}

}  // namespace
}  // namespace slipfit
