#pragma once
// The numeric kernels checked on arbitrary doubles (NaN, inf, denormals, huge values
// come straight from the bytes): weighted estimators and refinement, distances, the slippage
// matrix and its analysis, Bézier/NURBS torus evaluation. A kernel may refuse (a status, a
// degenerate verdict, an exception of the documented kinds) but must not crash, and a result it
// calls ok must be finite.
#include "slipfit/core/exceptions.h"
#include "slipfit/fitting/primitives.h"
#include "slipfit/fitting/weighted_fit.h"
#include "slipfit/slippage/slippage.h"
#include "slipfit/surfaces/torus.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace slipfit::fuzz {

inline bool finite(const slipfit::Primitive& p) {
  return slipfit::allFinite(p);
}

/// Runs the kernels on \a size bytes read as 7 doubles per point; aborts when a kernel reports
/// success with a non-finite number. Shared by the fuzz target and the regression test.
inline void checkKernels(const std::uint8_t* data, std::size_t size) {
  // 7 doubles per point: x y z, nx ny nz, weight.
  const std::size_t n = size / (7 * sizeof(double));
  if (n == 0 || n > 512)
    return;
  std::vector<double> v(n * 7);
  std::memcpy(v.data(), data, n * 7 * sizeof(double));
  Eigen::Matrix3Xd points(3, static_cast<Eigen::Index>(n)),
      normals(3, static_cast<Eigen::Index>(n));
  Eigen::VectorXd weights(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = static_cast<Eigen::Index>(i);
    points.col(c) << v[7 * i], v[7 * i + 1], v[7 * i + 2];
    normals.col(c) << v[7 * i + 3], v[7 * i + 4], v[7 * i + 5];
    weights[c] = v[7 * i + 6];
  }
  for (auto type : {slipfit::PrimitiveType::plane, slipfit::PrimitiveType::sphere,
                    slipfit::PrimitiveType::cylinder, slipfit::PrimitiveType::cone,
                    slipfit::PrimitiveType::torus}) {
    const slipfit::FitResult fit = slipfit::fitPrimitive(type, points, normals, weights);
    if (fit.ok() &&
        (!finite(fit.refined) || !finite(fit.algebraic) || !std::isfinite(fit.rms_distance)))
      std::abort();  // "ok" with NaN parameters
    if (fit.ok())
      (void)slipfit::distance(points.col(0), fit.refined);
  }
  const slipfit::FitResult best = slipfit::fitAuto(points, normals, weights);
  if (best.ok() && !finite(best.refined))
    std::abort();
  const slipfit::SlippageResult slip = slipfit::analyzeSlippage(points, normals, weights);
  if (slip.type != slipfit::SlippageType::degenerate && !slip.spectrum.allFinite())
    std::abort();
  if (slip.primitive && !finite(*slip.primitive))
    std::abort();
  try {
    const slipfit::TorusShape shape{v[0], v[1]};
    const slipfit::SurfacePoint s = slipfit::evaluateTorusBezier(shape, v[2], v[3]);
    if (std::isfinite(v[2]) && std::isfinite(v[3]) && std::abs(v[2]) < 1e6 &&
        std::abs(v[3]) < 1e6 && !s.position.allFinite())
      std::abort();
  } catch (const slipfit::InvalidParameterError&) {
  }
}

}  // namespace slipfit::fuzz
