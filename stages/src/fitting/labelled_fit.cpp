#include "slipfit/fitting/labelled_fit.h"

#include "slipfit/fitting/surface_noise.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace slipfit {

void LabelledFitParameters::validate() const {
  validateDeclared(*this, "primitive fitting");
  fit.validate();
  robust.validate();
}

namespace {

/// The tolerance of \a record's inliers (see the file comment), with its source.
void setInlierDistance(const LabelledFitParameters& p, bool robust, const Eigen::Matrix3Xd& points,
                       const Eigen::Matrix3Xd& normals, LabelledFit& record) {
  if (p.inlier_distance) {
    record.tolerance_source = "set in the config";
    record.inlier_distance = *p.inlier_distance;
    return;
  }
  if (robust && record.inlier_distance > 0.0) {
    // Outliers inflate any scale measured on all the points; the robust fit's own threshold was
    // set on the residuals of its consensus.
    record.tolerance_source = p.robust.threshold ? "robust_threshold, set in the config"
                                                 : "2.5 x the robust fit's residual scale";
    return;
  }
  constexpr int kNeighbors = 32, kFewest = 8;
  const int k = static_cast<int>(std::min<Eigen::Index>(kNeighbors, points.cols() - 1));
  if (k < kFewest) {
    record.tolerance_source = "3 x the fit's RMS distance (fewer than 9 points: no noise estimate)";
    record.inlier_distance = 3.0 * record.fit.rms_distance;
    return;
  }
  const double noise = normals.cols() == points.cols() ? estimateSurfaceNoise(points, normals, k)
                                                       : estimateSurfaceNoise(points, k);
  record.tolerance_source = "3 x the surface noise measured from the points";
  record.surface_noise = noise;
  record.inlier_distance = 3.0 * noise;
}

FitResult fitOne(const LabelledFitParameters& p, RobustMethod method,
                 const Eigen::Matrix3Xd& points, const Eigen::Matrix3Xd& normals,
                 const Eigen::VectorXd& w, std::uint64_t seed, double* limit) {
  if (method == RobustMethod::none)
    return p.type ? fitPrimitive(*p.type, points, normals, w, p.fit)
                  : fitAuto(points, normals, w, p.fit);
  RobustOptions robust = p.robust;
  robust.method = method;
  robust.seed = seed;
  if (p.type)
    return fitRobust(*p.type, points, normals, w, robust, p.fit, nullptr, limit);
  return fitRobustAuto(points, normals, w, robust, p.fit, limit);
}

}  // namespace

LabelledFits fitLabelled(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                         const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                         const std::vector<double>& weights, const std::vector<double>& labels,
                         const LabelledFitParameters& p, std::uint64_t seed) {
  p.validate();
  const auto n = static_cast<std::size_t>(points.cols());
  if (weights.size() != n || !(labels.empty() || labels.size() == n))
    throw InvalidParameterError("primitive fitting: weights and labels need one value per point");
  const bool whole = labels.empty();
  const RobustMethod method = p.robustMethod(whole);
  std::map<int, std::vector<Eigen::Index>> groups;
  if (whole) {
    auto& all = groups[-1];
    all.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      all[i] = static_cast<Eigen::Index>(i);
  } else {
    for (std::size_t i = 0; i < n; ++i)
      if (labels[i] >= 0.0 && std::isfinite(labels[i]))
        groups[static_cast<int>(labels[i])].push_back(static_cast<Eigen::Index>(i));
  }
  const bool with_normals = normals.cols() == points.cols() && normals.cols() > 0;
  LabelledFits out;
  out.distance.assign(n, -1.0f);
  for (const auto& [label, members] : groups) {
    LabelledFit record;
    if (label >= 0)
      record.label = label;
    const auto m = static_cast<Eigen::Index>(members.size());
    const Eigen::Matrix3Xd x = points(Eigen::all, members);
    const Eigen::Matrix3Xd nn =
        with_normals ? Eigen::Matrix3Xd(normals(Eigen::all, members)) : Eigen::Matrix3Xd(3, 0);
    Eigen::VectorXd w(m);
    for (Eigen::Index j = 0; j < m; ++j)
      w[j] = weights[static_cast<std::size_t>(members[static_cast<std::size_t>(j)])];
    if (static_cast<int>(members.size()) < p.min_points) {
      record.fit.status = FitStatus::too_few_points;
      record.fit.reason =
          std::to_string(members.size()) + " points, min_points is " + std::to_string(p.min_points);
    } else {
      record.fit = fitOne(p, method, x, nn, w, seed, &record.inlier_distance);
    }
    if (record.fit.ok()) {
      setInlierDistance(p, method != RobustMethod::none, x, nn, record);
      for (Eigen::Index j = 0; j < m; ++j) {
        const double d = distance(x.col(j), record.fit.refined);
        out.distance[static_cast<std::size_t>(members[static_cast<std::size_t>(j)])] =
            static_cast<float>(d);
        record.points += w[j] > 0.0 ? 1 : 0;
        if (w[j] > 0.0 && d <= record.inlier_distance)
          ++record.inliers;
      }
    }
    out.fits.push_back(std::move(record));
  }
  return out;
}

}  // namespace slipfit
