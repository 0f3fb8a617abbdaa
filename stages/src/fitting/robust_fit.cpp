#include "slipfit/fitting/robust_fit.h"
#include "slipfit/core/exceptions.h"
#include "slipfit/core/median.h"
#include "slipfit/fitting/model_selection.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

namespace slipfit {

namespace {

using Points = Eigen::Ref<const Eigen::Matrix3Xd>;
using Weights = Eigen::Ref<const Eigen::VectorXd>;

Eigen::VectorXd residuals(const Points& points, const Primitive& shape) {
  Eigen::VectorXd d(points.cols());
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    d[i] = points.col(i).allFinite() ? distance(points.col(i), shape) : 1e300;
  return d;
}

/// 1.4826 × the weighted-support median of |D| (the MAD scale of Gaussian residuals).
double robustScale(const Eigen::VectorXd& d, const Weights& weights) {
  std::vector<double> v;
  for (Eigen::Index i = 0; i < d.size(); ++i)
    if (weights[i] > 0.0)
      v.push_back(d[i]);
  if (v.empty())
    return 0.0;
  return 1.4826 * medianInPlace(v);
}

FitResult closedForm(PrimitiveType type, const Points& points, const Points& normals,
                     const Weights& w, const FitOptions& options) {
  FitOptions closed = options;
  closed.refine = false;
  return fitPrimitive(type, points, normals, w, closed);
}

}  // namespace

void RobustOptions::validate() const {
  validateDeclared(*this, "robust fit");
  if (irls_iterations < 1)
    throw InvalidParameterError("robust fit: irls_iterations must be at least 1, got " +
                                std::to_string(irls_iterations));
}

FitResult fitRobust(PrimitiveType type, const Points& points, const Points& normals,
                    const Weights& weights, const RobustOptions& robust, const FitOptions& options,
                    std::vector<char>* inliers, double* inlier_distance) {
  robust.validate();
  const Eigen::Index n = points.cols();
  FitResult start = fitPrimitive(type, points, normals, weights, options);
  if (robust.method == RobustMethod::none || (!start.ok() && robust.method == RobustMethod::irls)) {
    if (inliers)
      inliers->assign(static_cast<std::size_t>(n), 0);
    return start;
  }
  Primitive current = start.ok() ? start.refined : Primitive{};
  bool have = start.ok();

  if (robust.method == RobustMethod::ransac) {
    // Hypotheses from minimal samples of points with positive weight; score by the weight of the
    // points within the threshold (or, without one, by the least median of distances).
    std::vector<Eigen::Index> candidates;
    for (Eigen::Index i = 0; i < n; ++i)
      if (weights[i] > 0.0 && points.col(i).allFinite())
        candidates.push_back(i);
    const int k = minimumPoints(type) + 1;  // one spare point steadies the closed forms
    if (static_cast<int>(candidates.size()) >= k) {
      std::mt19937_64 rng(robust.seed);
      std::uniform_int_distribution<std::size_t> pick(0, candidates.size() - 1);
      Eigen::Matrix3Xd sp(3, k), sn(3, normals.cols() == n ? k : 0);
      const Eigen::VectorXd sw = Eigen::VectorXd::Ones(k);
      double best = -1.0;
      for (int it = 0; it < robust.ransac_iterations; ++it) {
        for (int j = 0; j < k; ++j) {
          const Eigen::Index i = candidates[pick(rng)];
          sp.col(j) = points.col(i);
          if (sn.cols())
            sn.col(j) = normals.col(i);
        }
        const FitResult h = closedForm(type, sp, sn, sw, options);
        if (!h.ok())
          continue;
        const Eigen::VectorXd d = residuals(points, h.algebraic);
        double score = 0.0;
        if (robust.threshold) {
          for (Eigen::Index i = 0; i < n; ++i)
            if (weights[i] > 0.0 && d[i] <= *robust.threshold)
              score += weights[i];
        } else {
          const double s = robustScale(d, weights);
          score = s > 0.0 ? 1.0 / s : 1e300;
        }
        if (score > best) {
          best = score;
          current = h.algebraic;
          have = true;
        }
      }
    }
    if (!have) {
      if (inliers)
        inliers->assign(static_cast<std::size_t>(n), 0);
      return start;
    }
  }

  // IRLS with Tukey's biweight ψ(u) = (1 − u²)² for |u| < 1, u = D / (4.685 σ).
  Eigen::VectorXd w = weights;
  FitResult fit = start;
  double scale = 0.0;
  for (int it = 0; it < robust.irls_iterations; ++it) {
    const Eigen::VectorXd d = residuals(points, current);
    scale = robust.threshold ? *robust.threshold / 2.5 : robustScale(d, weights);
    if (!(scale > 0.0))
      break;  // an exact fit: nothing to reweight
    const double c = 4.685 * scale;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double u = d[i] / c;
      w[i] = weights[i] > 0.0 && u < 1.0 ? weights[i] * (1.0 - u * u) * (1.0 - u * u) : 0.0;
    }
    const FitResult next = fitPrimitive(type, points, normals, w, options);
    if (!next.ok())
      break;
    fit = next;
    const double change = (residuals(points, next.refined) - d).cwiseAbs().maxCoeff();
    current = next.refined;
    if (change < 1e-9 * c)
      break;
  }
  const double limit = robust.threshold.value_or(2.5 * scale);
  if (inlier_distance)
    *inlier_distance = limit;
  if (inliers) {
    const Eigen::VectorXd d = residuals(points, fit.refined);
    inliers->resize(static_cast<std::size_t>(n));
    for (Eigen::Index i = 0; i < n; ++i)
      (*inliers)[static_cast<std::size_t>(i)] = weights[i] > 0.0 && d[i] <= limit;
  }
  return fit;
}

FitResult fitRobustAuto(const Points& points, const Points& normals, const Weights& weights,
                        const RobustOptions& robust, const FitOptions& options,
                        double* inlier_distance) {
  std::vector<FitResult> fits;
  double common = std::numeric_limits<double>::infinity();
  for (const auto& [type, name] : kPrimitiveTypeNames) {
    if ((type == PrimitiveType::cylinder || type == PrimitiveType::cone ||
         type == PrimitiveType::torus) &&
        normals.cols() != points.cols())
      continue;
    double limit = 0.0;
    const FitResult r = fitRobust(type, points, normals, weights, robust, options, nullptr, &limit);
    if (!r.ok() || isNearlyDegenerate(r.refined, points))
      continue;
    fits.push_back(r);
    if (limit > 0.0)
      common = std::min(common, limit);
  }
  FitResult best;
  best.status = FitStatus::degenerate;
  best.reason = "no primitive type fits robustly";
  double best_weight = -1.0;
  for (const FitResult& r : fits) {
    double weight = 0.0;
    for (Eigen::Index i = 0; i < points.cols(); ++i)
      if (weights[i] > 0.0 && distance(points.col(i), r.refined) <= common)
        weight += weights[i];
    if (weight > 1.01 * best_weight) {
      best_weight = weight;
      best = r;
    }
  }
  if (best.ok() && inlier_distance)
    *inlier_distance = common;
  return best;
}

}  // namespace slipfit
