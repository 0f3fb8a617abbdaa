#pragma once
/// \file The position noise of points sampled on a smooth surface, measured from the points
/// alone (no normals, no model): the scale against which a fitted primitive's residual says
/// "explained" or "not". Used by the whole-cloud shape classification (shape_classification.h).

#include <Eigen/Core>

namespace slipfit {

/// σ̂ of 3 × N points on a surface: for up to 2000 query points (every ⌈N/2000⌉-th), take the k
/// points nearest *along* the surface — among the 2k nearest in space, the k with the least
/// distance in the tangent plane — fit the quadric height h(s, t) over the tangent plane to them
/// (curvature, tilt and offset: 6 parameters) and take the RMS residual over k − 6 degrees of
/// freedom; σ̂ is the median over the queries. The tangent plane is the least-squares plane of
/// the 2k points. Choosing neighbours in space alone prefers the points that noise put at the
/// query's own height and reads noise near the sampling spacing low (0.92 σ on a plane sampled
/// at 1.4 σ, 0.87 σ on scan lines); from 4k, the ball of a tightly curved surface reaches an
/// opposite face that projects onto the same spot. The quadric leaves third-order shape only:
/// 0.002 on a helicoid, a vase and extrusions sampled at σ = 0.002. Non-finite points are
/// skipped; 0 for fewer than k + 1 finite points. k in [8, 64]; throws InvalidParameterError
/// otherwise.
double estimateSurfaceNoise(const Eigen::Ref<const Eigen::Matrix3Xd>& points, int k = 16);

/// As above, across each query point's own normal (any sign and length, one per point; a zero
/// or non-finite one falls back to the least-squares normal), which noise does not tilt.
double estimateSurfaceNoise(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                            const Eigen::Ref<const Eigen::Matrix3Xd>& normals, int k = 16);

/// The position noise and the tilt noise of the given normals.
struct SurfaceNoise {
  double position = 0.0;  ///< σ̂, as estimateSurfaceNoise with normals
  /// σ̂_t, radians: the standard deviation of each of the two tilt components of the given normals
  /// against the local quadric's normal at the query (the median squared tilt / 2 ln 2, the median
  /// of χ²₂). With exact normals it reads the quadric's own slope error; PCA normals of k
  /// neighbours within a radius R tilt by about 2 σ / (R √k).
  double normal_tilt = 0.0;
};

/// Both, from the same queries and quadrics.
SurfaceNoise estimateSurfaceAndNormalNoise(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                           const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                                           int k = 16);

}  // namespace slipfit
