#pragma once
/// \file A labelled test scene of any layout — the fixed one of scene_sampler.h, the random one of
/// random_scene_sampler.h or the kinematic one of kinematic_scene_sampler.h — with its options
/// declared once: the scene sampling stage's library side.

#include "slipfit/core/parameter_declaration.h"
#include "slipfit/fitting/primitives.h"
#include "slipfit/sampling/kinematic_scene_sampler.h"
#include "slipfit/sampling/random_scene_sampler.h"
#include "slipfit/sampling/scene_sampler.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string_view>
#include <utility>
#include <vector>

namespace slipfit {

enum class SceneLayout { fixed, random, kinematic };
constexpr std::array<std::pair<SceneLayout, std::string_view>, 3> kSceneLayoutNames{{
    {SceneLayout::fixed, "fixed"},
    {SceneLayout::random, "random"},
    {SceneLayout::kinematic, "kinematic"},
}};

struct LabelledSceneParameters {
  SceneLayout layout = SceneLayout::fixed;
  std::size_t shapes = 75;      ///< random layout
  double size = 0.25;           ///< random layout: the smallest shape size
  std::size_t points = 100000;  ///< surface samples (outliers come on top)
  /// σ of the position noise as a fraction of the object size; the random layout takes at most
  /// 0.05 (RandomSceneParameters).
  double noise = 0.0;
  double outlier_fraction = 0.0;
  std::uint64_t seed = 1;

  /// Each user-facing field with its one declaration (parameter_declaration.h).
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit(self.layout,
          parameter("layout",
                    "fixed: a box, cylinder, sphere and cone on a ground plane (10 primitives); "
                    "random: `shapes` shapes of all five types, sizes over 20×, random poses, "
                    "touching and cutting shapes, filleted L-brackets, 500–50,000 points each; "
                    "kinematic: a turned part, an extruded section and a threaded rod with a "
                    "cylinder and a sphere on a plate (truth_type 5 revolution, 6 extrusion, 7 "
                    "helix)."),
          kSceneLayoutNames);
    visit(self.shapes,
          parameter("shapes", "Random layout: number of primitives.").between(1, 10000));
    visit(self.size,
          parameter("size", "Random layout: the smallest shape size (the largest is 20 times it).")
              .in("units")
              .above(0));
    visit(self.points, parameter("points", "Surface samples (outliers come on top).")
                           .in("points")
                           .between(100, 1e9));
    visit(self.noise,
          parameter("noise",
                    "σ of Gaussian position noise as a fraction of the object size (fixed: the "
                    "box is 0.8 wide; random: the median shape size, at most 0.05).")
              .between(0, 0.1));
    visit(self.outlier_fraction,
          parameter("outliers",
                    "Outliers per surface sample, uniform in the scene's box (truth_label -1).")
              .between(0, 1));
  }

  /// The parameters of the layout's sampler.
  SceneSamplingParameters fixedLayout() const { return withShared(SceneSamplingParameters{}); }
  KinematicSceneParameters kinematicLayout() const {
    KinematicSceneParameters p;
    p.points = points;
    p.noise = noise;
    p.seed = seed;
    return p;
  }
  RandomSceneParameters randomLayout() const {
    RandomSceneParameters p = withShared(RandomSceneParameters{});
    p.shapes = shapes;
    p.size = size;
    return p;
  }

  /// Throws InvalidParameterError naming the field (the layout's own limits included).
  void validate() const;

 private:
  /// \a p with the options both layouts have.
  template <typename Layout>
  Layout withShared(Layout p) const {
    p.points = points;
    p.noise = noise;
    p.outlier_fraction = outlier_fraction;
    p.seed = seed;
    return p;
  }
};

struct LabelledScene {
  Eigen::Matrix3Xd points, normals;  ///< 3 × N, exact unit normals (outliers: random)
  std::vector<std::int32_t> labels;  ///< the true primitive of each point, −1 for outliers
  std::vector<std::int32_t> types;   ///< truthTypeCode of its truth, −1 for outliers
  std::vector<SurfaceTruth> truth;   ///< the true surfaces, indexed by label
};

/// Samples the scene of \a parameters' layout. Deterministic for given parameters.
LabelledScene sampleLabelledScene(const LabelledSceneParameters& parameters);

}  // namespace slipfit
