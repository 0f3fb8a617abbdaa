#pragma once
/// \file Levenberg–Marquardt on the normal equations, for problems with few parameters (p ≤ 10)
/// and many residuals: the primitives' refinement on the true distance (fit_refinement.cpp).
///
/// MINPACK's lmder (Eigen's unsupported LevenbergMarquardt) stores the m × p Jacobian and factors
/// it by a column-pivoted QR at every iteration, 2 m p² flops with little vectorization; here the
/// problem accumulates the p × p matrix JᵀJ and the gradient Jᵀf row by row, once per accepted
/// step (no m × p matrix is stored), and each trial step is a p × p Cholesky solve. Squaring the
/// condition number is harmless here: the refinement works in coordinates centred and scaled to
/// unit RMS radius, where the Jacobian's columns are of order 1, and a step the factorization
/// cannot take raises the damping instead (LDLᵀ of a matrix made positive definite by λ D).
///
/// Damping: Marquardt's scaled form (JᵀJ + λ D) δ = −Jᵀf with D the largest diagonal of JᵀJ seen
/// so far (MINPACK's scaling, invariant to the parameters' units), λ updated by the gain ratio ρ
/// as Nielsen (1999) does: λ ← λ · max(1/3, 1 − (2ρ − 1)³) on an accepted step, λ ← λ ν, ν ← 2ν on
/// a rejected one.
///
/// Problem: `void residuals(const Eigen::VectorXd& x, Eigen::VectorXd& f) const` (f sized m) and
/// `void normalEquations(const Eigen::VectorXd& x, const Eigen::VectorXd& f, Eigen::MatrixXd& A,
/// Eigen::VectorXd& g) const`, which sets the p × p A = JᵀJ (both triangles) and g = Jᵀf for the
/// Jacobian J of f at x, f being the residuals at x; p = x.size().

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <algorithm>
#include <cmath>

namespace slipfit {

struct LevenbergMarquardtSettings {
  int max_evaluations = 100;  ///< residual evaluations at most (MINPACK's maxfev), ≥ 1
  double relative_cost = 1e-14;  ///< stop when an accepted step lowers ‖f‖² by less than this share
  double relative_step = 1e-14;  ///< stop when ‖δ‖ ≤ this · (‖x‖ + this)
  /// λ₀ (dimensionless: the damping is λ D): the first step is all but Gauss–Newton's, as
  /// MINPACK's first trust region (100 ‖D x‖) allows. Measured on the suite: a damping of order
  /// one held the first steps of tori back enough to end a torus of the slippage tests (partial
  /// scan lines, 1 % noise) in another basin, RMS 12 times the noise; Nielsen's 1e-3 moved PCL's
  /// stereo table below 90 % of its tutorial plane's points (0.899).
  double initial_damping = 1e-6;
};

struct LevenbergMarquardtOutcome {
  int iterations = 0;   ///< accepted steps
  int evaluations = 0;  ///< residual evaluations, the first included
  double cost = 0.0;    ///< ‖f(x)‖² at the returned x
};

/// Minimises ‖f(x)‖² from \a x (changed in place to the best point found; never worse than the
/// start).
template <class Problem>
LevenbergMarquardtOutcome minimizeLevenbergMarquardt(const Problem& problem, Eigen::VectorXd& x,
                                                     const LevenbergMarquardtSettings& settings) {
  const Eigen::Index p = x.size();
  LevenbergMarquardtOutcome out;
  Eigen::VectorXd f, trial_f;
  problem.residuals(x, f);
  out.evaluations = 1;
  out.cost = f.squaredNorm();
  if (!std::isfinite(out.cost) || p == 0)
    return out;
  Eigen::MatrixXd normal(p, p), damped(p, p);
  Eigen::VectorXd gradient(p), scale = Eigen::VectorXd::Zero(p), step(p), trial(p);
  auto linearize = [&]() {
    problem.normalEquations(x, f, normal, gradient);
    scale = scale.cwiseMax(normal.diagonal());
  };
  linearize();
  double damping = settings.initial_damping;
  double growth = 2.0;
  Eigen::LDLT<Eigen::MatrixXd> ldlt(p);
  while (out.evaluations < settings.max_evaluations) {
    if (!(gradient.allFinite()) || gradient.cwiseAbs().maxCoeff() == 0.0)
      break;
    // The floor keeps D positive for a parameter the data do not move (a zero column).
    damped = normal;
    const double floor = 1e-300 + 1e-16 * scale.maxCoeff();
    damped.diagonal() += damping * scale.cwiseMax(floor);
    ldlt.compute(damped);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0.0).all()) {
      damping *= growth;
      growth *= 2.0;
      if (!std::isfinite(damping))
        break;
      continue;
    }
    step = ldlt.solve(-gradient);
    if (!step.allFinite())
      break;
    if (step.norm() <= settings.relative_step * (x.norm() + settings.relative_step))
      break;
    trial = x + step;
    problem.residuals(trial, trial_f);
    ++out.evaluations;
    const double trial_cost = trial_f.squaredNorm();
    // The decrease the linear model predicts: −(2 gᵀδ + δᵀ JᵀJ δ) = δᵀ(λ D δ − g) ≥ 0.
    const double predicted =
        step.dot((damping * scale.cwiseMax(floor)).cwiseProduct(step) - gradient);
    const double actual = out.cost - trial_cost;
    if (std::isfinite(trial_cost) && actual > 0.0 && predicted > 0.0) {
      const double rho = actual / predicted;
      x = trial;
      f.swap(trial_f);
      const double previous = out.cost;
      out.cost = trial_cost;
      ++out.iterations;
      const double t = 2.0 * rho - 1.0;
      damping *= std::max(1.0 / 3.0, 1.0 - t * t * t);
      growth = 2.0;
      if (actual <= settings.relative_cost * previous &&
          predicted <= settings.relative_cost * previous)
        break;
      linearize();
    } else {
      // Nothing left that the model predicts: the start of the step is a minimum to rounding.
      if (!(predicted > settings.relative_cost * out.cost))
        break;
      damping *= growth;
      growth *= 2.0;
      if (!std::isfinite(damping))
        break;
    }
  }
  return out;
}

}  // namespace slipfit
