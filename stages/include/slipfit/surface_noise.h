#pragma once
/// \file The position noise of points sampled on a smooth surface, measured from the points
/// alone (no normals, no model): the scale against which a fitted primitive's residual says
/// "explained" or "not". Used by the whole-cloud shape classification (shape_classification.h).

#include <Eigen/Core>

namespace slipfit {

/// σ̂ of 3 × N points on a surface: for up to 2000 query points (every ⌈N/2000⌉-th), the smallest
/// eigenvalue λ₀ of the covariance of its \a k nearest points (the mean squared distance from
/// their least-squares plane), times k / (k − 3) for the plane's three parameters; σ̂ is the
/// median of √ over the queries. Curvature adds the neighbourhood's sagitta, so on a clean
/// curved surface σ̂ is the local deviation from flatness, not 0. Non-finite points are skipped;
/// 0 for fewer than k + 1 finite points. k in [4, 64]; throws InvalidParameterError otherwise.
double estimateSurfaceNoise(const Eigen::Ref<const Eigen::Matrix3Xd>& points, int k = 16);

}  // namespace slipfit
