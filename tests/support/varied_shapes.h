#pragma once
/// \file Seeded families of varied single shapes for the whole-cloud slippage tests: the five
/// primitives in random poses and sizes with the nuisances of real data (noise, partial coverage,
/// density gradients, scan lines, estimated normals, flipped normals), and the one-motion
/// surfaces (vases, closed and open extrusions, helicoids, twisted columns) with their motion.

#include "slipfit/slippage/slippage.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>

namespace slipfit::testing {

/// What a varied cloud is, and how it was made (for the failure listing).
struct VariedShape {
  SlippageType truth = SlippageType::none;
  Eigen::Matrix3Xd points, normals;
  std::string description;
  /// The motion's axis direction, a point on it and its pitch per radian (one-motion surfaces).
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d axis_point = Eigen::Vector3d::Zero();
  double pitch = 0.0;
};

/// How a family is disturbed. The noise is a fraction of the shape's size: the smallest radius
/// of curvature of a curved primitive (the tube radius of a torus, the mean radius of a cone's
/// band), the half extent of a plane, the radius of a one-motion surface.
struct Disturbance {
  double noise = 0.0;
  bool estimated_normals = false;  ///< PCA normals of the k = 30 nearest points
  bool flips = true;               ///< half the normals of every other cloud flipped
};

/// PCA normals of the \a k nearest points of 3 × N points, estimated in float on the centred
/// cloud (as any PCL user with far-off data must); \a n is resized to 3 × N.
void estimatePcaNormals(const Eigen::Matrix3Xd& x, int k, Eigen::Matrix3Xd& n);

/// Cloud \a index of the primitive family of \a seed: type index % 5 (plane, sphere, cylinder,
/// cone, torus); size log-uniform in [1e-3, 1e3], every third cloud 1e3 sizes from the origin
/// (where float coordinates, as the pipeline's, still resolve 1e-4 of the size); cylinder height /
/// radius log-uniform in [0.15, 40], cone half-angles 5°–75°, torus r / R log-uniform in [0.06,
/// 0.8]; partial coverage on every other cloud; uniform, density-gradient or scan-line sampling in
/// turn; 4000 points.
VariedShape variedPrimitive(int index, std::uint64_t seed, const Disturbance& disturbance);

/// Cloud \a index of the one-motion family of \a seed: a vase, a closed or an open extrusion, a
/// helicoid or a twisted column in turn, random pose and size (log-uniform in [1e-3, 1e3], every
/// third cloud 1e3 sizes from the origin (where float
/// coordinates, as the pipeline's, still resolve 1e-4 of the size)), 4000 points.
VariedShape variedMotionSurface(int index, std::uint64_t seed, const Disturbance& disturbance);

}  // namespace slipfit::testing
