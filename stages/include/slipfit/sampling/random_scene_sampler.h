#pragma once
/// \file A random labelled scene for segmentation tests and benchmarks: shapes of all five types
/// with sizes over a 20× range, random poses, some touching or intersecting their neighbours,
/// L-brackets with a tangent fillet (plane – quarter cylinder – plane), 500 to 50,000 points per
/// shape (a log-uniform density per shape), Gaussian noise and uniform outliers. The truth of
/// every label (its primitive) comes with the samples.

#include "slipfit/fitting/primitives.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace slipfit {

struct RandomSceneParameters {
  std::size_t shapes = 75;       ///< shapes; a fillet bracket counts as 3 (its 3 primitives)
  std::size_t points = 1000000;  ///< surface samples in all (outliers come on top), >= 100
  /// Shape sizes (units) are log-uniform in [size, 20 · size]. > 0.
  double size = 0.25;
  /// σ of the Gaussian position noise, as a fraction of the median shape size. [0, 0.05].
  double noise = 0.0;
  double outlier_fraction = 0.0;  ///< outliers per surface sample, uniform in the scene's box
  std::uint64_t seed = 1;

  /// Throws InvalidParameterError naming the field.
  void validate() const;
};

/// Samples the scene: 3 × N points, unit normals (exact, before noise), per point the true label
/// (−1 for outliers); \a truth gets the primitive of each label. Deterministic for given
/// parameters. Types are drawn with the weights 31 : 10 : 16 : 7 : 11 (plane, sphere, cylinder,
/// cone, torus), a tenth of the draws are fillet brackets, and a fifth of the shapes are moved
/// to touch or cut the previous one.
void sampleRandomScene(const RandomSceneParameters& parameters, Eigen::Matrix3Xd& points,
                       Eigen::Matrix3Xd& normals, std::vector<std::int32_t>& labels,
                       std::vector<Primitive>& truth);

/// A primitive moved by the rigid motion x ↦ R x + t.
Primitive transformed(const Primitive& primitive, const Eigen::Matrix3d& rotation,
                      const Eigen::Vector3d& translation);

}  // namespace slipfit
