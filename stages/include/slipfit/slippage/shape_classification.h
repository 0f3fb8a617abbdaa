#pragma once
/// \file What one whole point set is: a primitive (plane, sphere, cylinder, cone, torus), a
/// kinematic surface without one (revolution, extrusion, helix), or none. The slippage spectrum
/// proposes (slippage.h: its readings and their axes), the geometry decides: a primitive is the
/// answer when a fit of it (a) explains the positions — its RMS distance within
/// kExplainedNoiseRatio × the surface noise measured from the points (surface_noise.h) — and
/// (b) its own ideal motions slip on the normals, within the spectrum's gap; of the primitives that
/// do, the simplest adequate one (model_selection.h). When none does, the one-motion reading of
/// the spectrum is the answer. Positions alone cannot tell a short band of a cylinder from a
/// sphere at 1 % noise, nor normals alone a vase from a cylinder; together they do. Derivation:
/// docs/THEORY.md §5.4.

#include "slipfit/fitting/kinematic_fit.h"
#include "slipfit/fitting/weighted_fit.h"
#include "slipfit/slippage/slippage.h"

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace slipfit {

/// A primitive explains the points when its RMS distance is at most this many times the
/// measured surface noise (plus the rounding floor). For Gaussian noise σ the true surface's RMS
/// is σ and the noise estimate σ̂ ≈ 0.99 σ; a missed systematic deviation δ raises the RMS to
/// √(σ² + δ²/2), above 2 σ̂ once δ ≳ 2.4 σ.
constexpr double kExplainedNoiseRatio = 2.0;

/// The spectrum's threshold for a slippable motion is raised to this many times the energy that
/// the measured position and normal noise give an exact motion (ShapeClassification::
/// noise_energy): the sum over thousands of points concentrates at its mean, and the estimate
/// of the normals' tilt noise is itself within a factor of about 1.5.
constexpr double kNoiseEnergyRatio = 3.0;
/// ... but to no more than this: where noise gives an exact motion a quarter of the largest
/// energy, the spectrum no longer tells motions apart and the fits decide.
constexpr double kMostNoiseThreshold = 0.25;

/// One primitive type tried on the whole set.
struct ShapeCandidate {
  PrimitiveType type = PrimitiveType::plane;
  bool fitted = false;  ///< a fit exists (not failed, not in its simpler limit)
  double rms = 0.0;     ///< RMS point-to-surface distance of the best fit, units
  /// The largest relative slippage energy of the fit's ideal motions, and the spectrum's bound
  /// for k motions (k: the type's): √(λ_k λ_{k+1}), each raised to the noise floor. Reported:
  /// with estimated normals the energy can exceed the bound on a true primitive (scan lines
  /// leave PCA normals poor across the lines), so the positions decide.
  double energy = 0.0;
  double energy_bound = 0.0;
  bool explains = false;  ///< rms within kExplainedNoiseRatio × noise + floor
  bool slips = false;     ///< energy ≤ energy_bound
};

struct ShapeClassification {
  /// The verdict: type, motion count, axis / point / centre / normal / pitch, and for a primitive
  /// its refined fit (`primitive`). spectrum and gap are the spectrum's.
  SlippageResult verdict;
  std::optional<FitResult> fit;  ///< the verdict's primitive fit
  /// The kinematic surface (revolution, extrusion, helix) fitted from the spectrum's one-motion
  /// reading, when there is one and it could decide the verdict: no primitive explains the
  /// points, the spectrum reads one motion, or the best primitive is a one-motion type (cone,
  /// torus). It is the verdict when it explains the points and has the least BIC, its profile's
  /// vertices counted as parameters (kinematic_surface.h).
  std::optional<KinematicFit> kinematic;
  bool kinematic_explains = false;  ///< its RMS within kExplainedNoiseRatio × noise + floor
  bool kinematic_verdict = false;   ///< the verdict is the kinematic surface
  double noise = 0.0;               ///< the measured surface noise σ̂, units
  /// The relative energy (spectrum scale) that the measured noise gives the least-energy motion
  /// were it exact; the motions are read below max(threshold, kNoiseEnergyRatio × it).
  double noise_energy = 0.0;
  double floor = 0.0;  ///< the rounding floor of the distances, units
  /// With a fit: the points within inlier_distance = max(3 σ̂, floor) of it — judged against the
  /// noise measured from the points, not the fit's own RMS (which would call most points of any
  /// fit inliers).
  double inlier_distance = 0.0;
  std::size_t inliers = 0;
  std::vector<ShapeCandidate> candidates;  ///< one per primitive type, in kPrimitiveTypeNames order
  /// The spectrum's own reading (what analyzeSlippage reports), for comparison.
  SlippageResult spectral;
};

/// Classifies 3 × N points with normals (any sign and length) and weights (zero weight: ignored).
/// Degenerate input gives verdict.type == degenerate with the reason.
ShapeClassification classifyShape(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                  const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                                  const Eigen::Ref<const Eigen::VectorXd>& weights,
                                  const SlippageOptions& options = {});

/// The slippage type of a kinematic surface's class (revolution, extrusion, helix).
SlippageType slippageTypeOf(KinematicType type);

/// Number of rigid motions that slide a primitive of \a type along itself: 3 (plane, sphere), 2
/// (cylinder), 1 (cone, torus).
int motionCount(PrimitiveType type);

}  // namespace slipfit
