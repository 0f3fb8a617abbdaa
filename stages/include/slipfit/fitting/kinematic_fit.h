#pragma once
/// \file Fitting a kinematic surface (kinematic_surface.h) to points: from the motion that the
/// slippage analysis reads (an axis, a point on it, a pitch), the profile is fitted in the motion's
/// profile plane (profile_curve.h) and the motion refined by Levenberg–Marquardt on the points'
/// distances with the profile refitted at each step (variable projection), in rounds, in
/// coordinates centred on the points and scaled to unit RMS radius (docs/THEORY.md §5.5).

#include "slipfit/fitting/kinematic_surface.h"
#include "slipfit/fitting/weighted_fit.h"

#include <Eigen/Core>

#include <string>

namespace slipfit {

struct KinematicFit {
  KinematicSurface surface;
  FitStatus status = FitStatus::ok;
  std::string reason;           ///< why the fit failed, or "" when ok
  double rms_distance = 0.0;    ///< over the points with positive weight, weighted
  std::size_t used_points = 0;  ///< points with positive weight
  /// The least tolerance of the profile polyline, units: kProfileTolerance of the points' RMS
  /// radius. Below the noise, the profile follows the noise; below this, it does not.
  double tolerance = 0.0;
  bool ok() const { return status == FitStatus::ok; }
};

/// The start of a fit: the motion.
struct KinematicStart {
  KinematicType type = KinematicType::revolution;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  ///< any length ≠ 0
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< on the axis (revolution, helix)
  double pitch = 0.0;                               ///< helix, ≠ 0
};

/// Fits 3 × N \a points with \a weights (≥ 0; zero: ignored) from \a start. \a noise: the
/// points' position noise σ (surface_noise.h), units, ≥ 0 — the profile's vertices are as few as
/// it allows, down to kProfileTolerance. Up to kProfilePoints points (every
/// ⌈N / kProfilePoints⌉-th) fit the profile, up to kMotionPoints of those the motion; the RMS is
/// over all. Fails with the reason for too few points (20), a non-finite start or value, a zero
/// pitch for a helix, or a profile that cannot be ordered.
KinematicFit fitKinematicSurface(const KinematicStart& start,
                                 const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                 const Eigen::Ref<const Eigen::VectorXd>& weights, double noise);

/// Points of a fit's subsets (see fitKinematicSurface): the profile's, and the motion's.
constexpr std::size_t kProfilePoints = 4000;
constexpr std::size_t kMotionPoints = 1500;
/// The least tolerance of a profile, relative to the points' RMS radius: noise-free points would
/// otherwise ask for a vertex every few points (hundreds), each of which costs every projection.
/// A circle of radius 1 is then about 70 segments.
constexpr double kProfileTolerance = 1e-3;

}  // namespace slipfit
