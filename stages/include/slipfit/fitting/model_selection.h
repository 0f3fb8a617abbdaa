#pragma once
/// \file The one rule by which slipfit chooses a primitive type: the simplest adequate model.
/// A plane is a cylinder or sphere of infinite radius and a cone of 90°; a sphere is a torus with
/// R = 0; a cylinder is a torus with R → ∞ and a cone of 0°. Near those limits the more complex
/// type always fits a little better (it has more parameters), so residuals alone would never pick
/// the plane. The rule: a type is adequate when its RMS distance is within a margin of the best
/// type's (plus a floor for noise-free data); of the adequate types the one with the fewest
/// parameters wins. Derivation: docs/THEORY.md §4.4. Used by fitAuto (and so by the segmentation
/// and the primitive_fitting stage) and by the whole-cloud slippage verdict.

#include "slipfit/fitting/primitives.h"

#include <Eigen/Core>

#include <cstddef>
#include <optional>
#include <vector>

namespace slipfit {

/// A fitted type and its RMS point-to-surface distance over the same points (units).
struct ModelCandidate {
  PrimitiveType type = PrimitiveType::plane;
  double rms = 0.0;
};

/// Relative margin of adequacy: a type whose RMS is at most (1 + this) × the best RMS explains
/// the data as well as the best (for Gaussian noise σ: a systematic deviation δ the simpler type
/// misses raises its RMS to √(σ² + δ²/2), within 25 % while δ ≲ 1.06 σ — not demanded by the
/// data). Fit4CAD: 0.25 against 0.1 raised the type accuracy from 0.949 to 0.958 (Dice 0.873 →
/// 0.871).
constexpr double kAdequacyMargin = 0.25;

/// A sphere or cylinder whose radius exceeds this many times the spread of the points across it
/// (their RMS distance from the centroid; for a cylinder, across its axis), a cone whose radius
/// of curvature at the points does (distance from the axis / cos of the half-angle: a cone near
/// 90°) or whose apex is farther from the points (their RMS distance: a cone near 0°, whose radius
/// changes over the points by under 1/50 of itself), or a torus whose major or minor radius does,
/// is its simpler limit (plane; plane; plane or cylinder; cylinder or sphere or plane) however
/// well it fits: over the points it bends by less than 1/(8·50) of their extent — within a sensor's
/// systematic distortion (a Kinect's table is a sphere of radius 54 m over 1.5 m, 2.3 mm closer to
/// it than the plane's 3 mm), and on CAD data an arc of under about 4°.
constexpr double kFlatRadiusRatio = 50.0;

/// True when \a primitive is in the degenerate limit above for \a points (3 × N).
bool isNearlyDegenerate(const Primitive& primitive,
                        const Eigen::Ref<const Eigen::Matrix3Xd>& points);

/// Number of free parameters of a type: 3, 4, 5, 6, 7 (plane, sphere, cylinder, cone, torus).
int parameterCount(PrimitiveType type);

/// Whether one primitive is the better model of n points than two (each on its own part), by the
/// Bayesian information criterion under Gaussian residuals: n ln(RSS/n) + p ln n is lower for the
/// one, i.e. n ln(\a rss_joint / \a rss_separate) ≤ \a saved_parameters ln n, where
/// saved_parameters is what the second primitive costs. The residual sums of squares in units²;
/// with rss_separate = 0 only rss_joint = 0 is better.
bool jointModelIsBetter(double rss_joint, double rss_separate, std::size_t n, int saved_parameters);

/// Index of the simplest adequate candidate: adequate when rms ≤ (1 + kAdequacyMargin) × the
/// least rms + \a floor (units; the noise level below which distances carry no information —
/// rounding for noise-free data), fewest parameters first, then the smaller rms, then the
/// earlier candidate. Candidates with a non-finite rms are skipped; nullopt when none is left.
std::optional<std::size_t> selectSimplest(const std::vector<ModelCandidate>& candidates,
                                          double floor);

}  // namespace slipfit
