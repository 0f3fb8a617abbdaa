// Phase 1 (estimate_scale): the noise, the spacing and each point's distance tolerance.
#include "phases.h"
#include "thin_wall.h"

#include "slipfit/core/exceptions.h"
#include "slipfit/core/median.h"
#include "slipfit/neighborhoods/depth_quantization.h"
#include "slipfit/segmentation/segmentation_tuning.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <tuple>

namespace slipfit::phases {

namespace {

using T = SegmentationTuning;

/// q-quantile of χ²_ν / ν by the Wilson–Hilferty approximation, for the z-score \a z of q.
double chiSquareQuantileOverDof(double nu, double z) {
  const double c = 2.0 / (9.0 * nu);
  return std::pow(std::max(0.0, 1.0 - c + z * std::sqrt(c)), 3.0);
}

/// The tolerance from the data: the noise from the spread of each neighborhood off its best
/// plane, the spacing the distance to the nearest other point.
struct DataScale {
  double noise = 0.0;    ///< σ̂, from the lower quartile of the neighborhoods' plane residuals
  double spacing = 0.0;  ///< median nearest-neighbor distance
};

/// Residual sum of squares of the height field h = a u² + b uv + c v² + d u + e v + f fitted
/// to the points \a idx in the frame of their principal axes (h along the least one).
double quadricResidual(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                       const std::vector<pcl::index_t>& idx, const Eigen::Vector3d& mean,
                       const Eigen::Matrix3d& axes) {
  const auto k = static_cast<Eigen::Index>(idx.size());
  Eigen::MatrixXd a(k, 6);
  Eigen::VectorXd h(k);
  double scale = 0.0;
  for (Eigen::Index j = 0; j < k; ++j) {
    const Eigen::Vector3d d =
        axes.transpose() * (points.col(idx[static_cast<std::size_t>(j)]) - mean);
    scale = std::max(scale, std::abs(d(1)) + std::abs(d(2)));
    h(j) = d(0);
    a.row(j) << d(1) * d(1), d(1) * d(2), d(2) * d(2), d(1), d(2), 1.0;
  }
  if (!(scale > 0.0))
    return 0.0;
  // Normalised columns (the quadratic ones scale as scale², the linear as scale).
  const double s2 = scale * scale;
  a.col(0) /= s2;
  a.col(1) /= s2;
  a.col(2) /= s2;
  a.col(3) /= scale;
  a.col(4) /= scale;
  const Eigen::VectorXd x = a.colPivHouseholderQr().solve(h);
  return (a * x - h).squaredNorm();
}

/// The mean and principal axes (least variance first) of the points \a idx.
std::pair<Eigen::Vector3d, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>> principalFrame(
    const Eigen::Ref<const Eigen::Matrix3Xd>& points, const std::vector<pcl::index_t>& idx) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (pcl::index_t j : idx)
    mean += points.col(j);
  mean /= static_cast<double>(idx.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (pcl::index_t j : idx) {
    const Eigen::Vector3d d = points.col(j) - mean;
    cov += d * d.transpose();
  }
  cov /= static_cast<double>(idx.size());
  return {mean, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov)};
}

/// \a layered: the cloud's depth is recorded on levels (detectQuantizedAxis), whose layers in a
/// neighborhood are part of its spread, not sheets of a thin wall.
DataScale dataScale(const Eigen::Ref<const Eigen::Matrix3Xd>& points, const Neighborhoods& hoods,
                    bool layered) {
  std::vector<double> variance, spacing;
  const std::size_t n = hoods.size();
  const std::size_t stride = std::max<std::size_t>(1, n / T::noise_sample);
  for (std::size_t i = 0; i < n; i += stride) {
    const NeighborView v = hoods[i];
    if (v.size() < 5)
      continue;
    spacing.push_back(std::sqrt(static_cast<double>(v.sqr_distances[1])));
    std::vector<pcl::index_t> idx(v.begin(), v.end());
    auto [mean, eigen] = principalFrame(points, idx);
    if (!layered) {
      std::vector<pcl::index_t> sheet =
          ownSheet(points, idx, static_cast<pcl::index_t>(i), eigen.eigenvectors(),
                   std::sqrt(static_cast<double>(v.sqr_distances[v.size() - 1])));
      if (sheet.size() < idx.size()) {
        if (sheet.size() < 5)
          continue;
        idx = std::move(sheet);
        std::tie(mean, eigen) = principalFrame(points, idx);
      }
    }
    const double k = static_cast<double>(idx.size());
    // The noise is what a smooth surface does not explain. With k ≥ 10 points the surface is the
    // local quadric height field (6 parameters: curvature is not noise — on sparse CAD parts the
    // plane's residual λ₀ is the sagitta of the curved faces, not noise); with fewer, the plane
    // (3). With Gaussian noise σ the residual sum of squares is σ² χ²_ν, ν = k − parameters. Each
    // neighborhood's value is scaled by the lower quartile of χ²_ν / ν, so that the lower
    // quartile over all neighborhoods estimates σ²: robust to the half of them that straddle
    // edges (the median was not). A thin wall puts both faces in all of them: the point's own
    // sheet is fitted (ownSheet).
    double rss = 0.0, nu = 0.0;
    if (idx.size() >= 10) {
      rss = quadricResidual(points, idx, mean, eigen.eigenvectors());
      nu = k - 6.0;
    } else {
      rss = std::max(0.0, eigen.eigenvalues()(0)) * k;
      nu = k - 3.0;
    }
    variance.push_back(rss / nu / chiSquareQuantileOverDof(nu, T::noise_quantile_z));
  }
  return {std::sqrt(quantile(std::move(variance), T::noise_quantile)),
          quantile(std::move(spacing), 0.5)};
}

}  // namespace

void estimateScale(SegmentationState& s) {
  // A coordinate recorded on levels (Kinect-like depth) puts a point up to half a step off its
  // surface along that axis, and a disparity sensor's noise grows with depth as its step does
  // (about half a step): each point's tolerance adds T::step_factor local steps to the tolerance
  // from the noise and spacing.
  s.result.lattice = detectQuantizedAxis(s.points);
  s.result.step_factor = s.result.lattice.detected() ? T::step_factor : 0.0;
  const DataScale scale = dataScale(s.points, s.hoods, s.result.lattice.detected());
  // Distances closer than the floor of noise-free data (a twentieth of the spacing) cannot tell
  // two primitives apart: see shareEdges.
  s.edge_margin = T::spacing_factor * scale.spacing;
  s.spacing = scale.spacing;
  s.result.noise = scale.noise;
  s.result.noise_factor = s.parameters.distance ? 0.0 : T::noise_factor;
  s.result.distance = s.parameters.distance.value_or(T::noise_factor * scale.noise +
                                                     T::spacing_factor * scale.spacing);
  if (!(s.result.distance > 0.0))
    throw DegenerateInputError(
        "segmentation: cannot derive a distance tolerance (all points coincide); set distance");
  s.result.max_angle = s.parameters.max_angle;
  std::vector<double> tolerance(s.n);
  for (std::size_t i = 0; i < s.n; ++i)
    tolerance[i] = s.result.tolerance(s.points.col(static_cast<Eigen::Index>(i)));
  s.result.min_points = s.parameters.min_points.value_or(T::default_min_points);
  s.result.labels.assign(s.n, -1);
  s.grower.emplace(s.points, s.normals, s.hoods, std::move(tolerance), s.result.max_angle);
  s.tried.assign(s.n, 0);
}

}  // namespace slipfit::phases
