// The normal-equation Levenberg–Marquardt kernel on problems whose minima are known exactly.
#include "slipfit/fitting/levenberg_marquardt.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include <cmath>
#include <random>

namespace slipfit {
namespace {

/// The normal equations from a problem's Jacobian (the problems below give J; the kernel asks
/// for JᵀJ and Jᵀf).
template <class WithJacobian>
struct FromJacobian : WithJacobian {
  void normalEquations(const Eigen::VectorXd& x, const Eigen::VectorXd& f, Eigen::MatrixXd& a,
                       Eigen::VectorXd& g) const {
    Eigen::MatrixXd j;
    this->jacobian(x, j);
    a = j.transpose() * j;
    g = j.transpose() * f;
  }
};

// Rosenbrock as least squares: f = (10 (x₂ − x₁²), 1 − x₁), minimum 0 at (1, 1), reached along
// the curved valley from the classical start (−1.2, 1).
struct RosenbrockJ {
  void residuals(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
    f.resize(2);
    f << 10.0 * (x[1] - x[0] * x[0]), 1.0 - x[0];
  }
  void jacobian(const Eigen::VectorXd& x, Eigen::MatrixXd& j) const {
    j.resize(2, 2);
    j << -20.0 * x[0], 10.0, -1.0, 0.0;
  }
};

TEST(LevenbergMarquardt, RosenbrocksValleyEndsAtItsMinimum) {
  Eigen::VectorXd x(2);
  x << -1.2, 1.0;
  const LevenbergMarquardtOutcome out =
      minimizeLevenbergMarquardt(FromJacobian<RosenbrockJ>{}, x, LevenbergMarquardtSettings{});
  // The residual is zero at the minimum and the Jacobian regular there: quadratic convergence
  // takes x to rounding (|δx| ~ 1e-16 · κ, κ(J) ≈ 20 at (1, 1)).
  EXPECT_NEAR(x[0], 1.0, 1e-12);
  EXPECT_NEAR(x[1], 1.0, 1e-12);
  EXPECT_LT(out.cost, 1e-24);
  EXPECT_LE(out.evaluations, 100);
}

// A linear problem A x ≈ b with a non-zero residual: the minimum is the least-squares solution,
// which a Householder QR gives to rounding; LM must end on it, whatever the start.
struct LinearJ {
  Eigen::MatrixXd a;
  Eigen::VectorXd b;
  void residuals(const Eigen::VectorXd& x, Eigen::VectorXd& f) const { f = a * x - b; }
  void jacobian(const Eigen::VectorXd&, Eigen::MatrixXd& j) const { j = a; }
};

TEST(LevenbergMarquardt, ALinearProblemEndsOnItsLeastSquaresSolution) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  FromJacobian<LinearJ> problem;
  problem.a.resize(200, 6);
  problem.b.resize(200);
  for (Eigen::Index i = 0; i < 200; ++i) {
    for (Eigen::Index j = 0; j < 6; ++j)
      problem.a(i, j) = g(rng);
    problem.b[i] = g(rng);
  }
  const Eigen::VectorXd best = problem.a.householderQr().solve(problem.b);
  Eigen::VectorXd x = Eigen::VectorXd::Constant(6, 5.0);
  const LevenbergMarquardtOutcome out =
      minimizeLevenbergMarquardt(problem, x, LevenbergMarquardtSettings{});
  // The kernel stops once a step lowers the cost by under 1e-14 of it, so the excess cost left,
  // δᵀ AᵀA δ, is below that: ‖δ‖ ≤ √(1e-14 · cost / λ_min(AᵀA)) (rounding, ε κ² ‖x‖ ≈ 1e-15 with
  // κ(A) ≈ 1.4, is far below).
  const double least = (problem.a * best - problem.b).squaredNorm();
  const Eigen::MatrixXd normal = problem.a.transpose() * problem.a;
  const double lambda_min = normal.selfadjointView<Eigen::Lower>().eigenvalues().minCoeff();
  EXPECT_LT((x - best).norm(), std::sqrt(1e-14 * least / lambda_min));
  EXPECT_NEAR(out.cost, least, 1e-14 * least);
}

// A circle fit by its geometric distance, f = ‖p − c‖ − r: exact points on a circle of radius 2
// about (1, −3) end on it from a poor start.
struct CircleJ {
  Eigen::Matrix2Xd p;
  void residuals(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
    f.resize(p.cols());
    for (Eigen::Index i = 0; i < p.cols(); ++i)
      f[i] = (p.col(i) - x.head<2>()).norm() - x[2];
  }
  void jacobian(const Eigen::VectorXd& x, Eigen::MatrixXd& j) const {
    j.resize(p.cols(), 3);
    for (Eigen::Index i = 0; i < p.cols(); ++i) {
      const Eigen::Vector2d d = p.col(i) - x.head<2>();
      j.row(i).head<2>() = -d.transpose() / d.norm();
      j(i, 2) = -1.0;
    }
  }
};

TEST(LevenbergMarquardt, ExactPointsOfACircleGiveItsCentreAndRadius) {
  FromJacobian<CircleJ> problem;
  problem.p.resize(2, 12);
  for (int i = 0; i < 12; ++i) {
    const double t = 0.4 * i;  // an arc of 4.4 rad
    problem.p.col(i) << 1.0 + 2.0 * std::cos(t), -3.0 + 2.0 * std::sin(t);
  }
  Eigen::VectorXd x(3);
  x << 0.0, 0.0, 1.0;
  minimizeLevenbergMarquardt(problem, x, LevenbergMarquardtSettings{});
  EXPECT_NEAR(x[0], 1.0, 1e-10);
  EXPECT_NEAR(x[1], -3.0, 1e-10);
  EXPECT_NEAR(x[2], 2.0, 1e-10);
}

TEST(LevenbergMarquardt, KeepsToItsEvaluationBudgetAndNeverEndsWorseThanItsStart) {
  Eigen::VectorXd x(2);
  x << -1.2, 1.0;
  Eigen::VectorXd f;
  RosenbrockJ{}.residuals(x, f);
  const double start = f.squaredNorm();
  LevenbergMarquardtSettings settings;
  settings.max_evaluations = 3;
  const LevenbergMarquardtOutcome out =
      minimizeLevenbergMarquardt(FromJacobian<RosenbrockJ>{}, x, settings);
  EXPECT_LE(out.evaluations, 3);
  RosenbrockJ{}.residuals(x, f);
  EXPECT_DOUBLE_EQ(out.cost, f.squaredNorm());
  EXPECT_LE(out.cost, start);
}

// A parameter the residuals do not depend on (a zero Jacobian column) must not break the solve:
// it stays where it started and the others reach their minimum.
struct WithAFreeParameterJ {
  void residuals(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
    f.resize(2);
    f << x[0] - 3.0, 2.0 * (x[0] + 1.0);
  }
  void jacobian(const Eigen::VectorXd&, Eigen::MatrixXd& j) const {
    j.resize(2, 2);
    j << 1.0, 0.0, 2.0, 0.0;
  }
};

TEST(LevenbergMarquardt, AParameterTheResidualsIgnoreStaysPut) {
  Eigen::VectorXd x(2);
  x << 0.0, 0.5;
  minimizeLevenbergMarquardt(FromJacobian<WithAFreeParameterJ>{}, x, LevenbergMarquardtSettings{});
  // min (x − 3)² + 4 (x + 1)² = 12.8 at x = (3 − 4)/5 = −0.2. The kernel stops once a step lowers
  // the cost by under 1e-14 of it: the excess 5 δx² left is below that, δx ≤ √(1e-14 · 12.8 / 5)
  // = 1.6e-7.
  EXPECT_NEAR(x[0], -0.2, 1.6e-7);
  EXPECT_EQ(x[1], 0.5);
}

}  // namespace
}  // namespace slipfit
