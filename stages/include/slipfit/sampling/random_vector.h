#pragma once
/// \file A vector of random draws in a fixed order. C++ leaves unspecified the order in which a
/// call's arguments are evaluated: `Eigen::Vector3d(g(rng), g(rng), g(rng))` takes its x from the
/// third draw under g++ and from the first under clang++, so one seed made two clouds. The draws
/// here are separate statements, the last coordinate drawn first: g++'s order, in which every
/// seed quoted in the project's figures and tests was drawn.

#include <Eigen/Core>

namespace slipfit {

/// N draws of \a distribution from \a engine, coordinate N − 1 first.
template <int N, class Distribution, class Engine>
Eigen::Matrix<typename Distribution::result_type, N, 1> randomVector(Distribution& distribution,
                                                                     Engine& engine) {
  Eigen::Matrix<typename Distribution::result_type, N, 1> v;
  for (int i = N - 1; i >= 0; --i)
    v(i) = distribution(engine);
  return v;
}

}  // namespace slipfit
