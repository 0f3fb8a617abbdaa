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
  /// The sampled neighborhoods that span a surface (not drawn out along a line): their centre
  /// points and variance estimates (each scaled so that their T::local_noise_quantile estimates
  /// σ²).
  std::vector<pcl::index_t> sampled;
  std::vector<double> variance;
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

/// The median absolute deviation of \a values from their median.
double medianDeviation(std::vector<double> values) {
  const double centre = quantile(values, 0.5);
  for (double& v : values)
    v = std::abs(v - centre);
  return quantile(std::move(values), 0.5);
}

/// Whether the points \a idx spread across their line: the median absolute deviation of their
/// coordinates along the second principal axis is at least T::least_aspect times that along the
/// first (deviations from the median, not the mean: a few points of the next row pull the mean).
bool spansASurface(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                   const std::vector<pcl::index_t>& idx, const Eigen::Matrix3d& axes) {
  std::vector<double> along, across;
  for (pcl::index_t j : idx) {
    along.push_back(points.col(j).dot(axes.col(2)));
    across.push_back(points.col(j).dot(axes.col(1)));
  }
  return medianDeviation(std::move(across)) >= T::least_aspect * medianDeviation(std::move(along));
}

/// What one sampled neighborhood gives dataScale.
struct SampleScale {
  bool has_spacing = false;   ///< at least 5 points: its nearest-neighbor distance counts
  bool has_variance = false;  ///< a sheet of at least 5 points: its variance estimate counts
  bool spans = false;         ///< it spans a surface: a sample of the local noise
  double spacing = 0.0, variance = 0.0, local_variance = 0.0;
};

/// The scale of point \a i's neighborhood (see dataScale).
SampleScale sampleScale(const Eigen::Ref<const Eigen::Matrix3Xd>& points, const NeighborView& v,
                        std::size_t i, bool layered) {
  SampleScale out;
  if (v.size() < 5)
    return out;
  out.has_spacing = true;
  out.spacing = std::sqrt(static_cast<double>(v.sqr_distances[1]));
  std::vector<pcl::index_t> idx(v.begin(), v.end());
  auto [mean, eigen] = principalFrame(points, idx);
  if (!layered) {
    std::vector<pcl::index_t> sheet =
        ownSheet(points, idx, static_cast<pcl::index_t>(i), eigen.eigenvectors(),
                 std::sqrt(static_cast<double>(v.sqr_distances[v.size() - 1])));
    if (sheet.size() < idx.size()) {
      if (sheet.size() < 5)
        return out;
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
  out.has_variance = true;
  out.variance = rss / nu / chiSquareQuantileOverDof(nu, T::noise_quantile_z);
  // A neighborhood drawn out along a line (a LiDAR's scan line on far ground, one row of a
  // grid, perhaps with a few points of the next row) says nothing of the noise: a sensor's
  // noise lies along its rays, and the points of one row displaced along their rays lie on one
  // plane (the row's cone of rays), which the height field fits. The local noise (localNoise)
  // does not use it. Medians, not the spread: two points of the next row must not pass for a
  // surface.
  out.spans = spansASurface(points, idx, eigen.eigenvectors());
  out.local_variance = rss / nu / chiSquareQuantileOverDof(nu, T::local_noise_quantile_z);
  return out;
}

/// \a layered: the cloud's depth is recorded on levels (detectQuantizedAxis), whose layers in a
/// neighborhood are part of its spread, not sheets of a thin wall. The sampled neighborhoods are
/// computed on \a workers threads, each into its own slot, and gathered in order: the result does
/// not depend on the threads.
DataScale dataScale(const Eigen::Ref<const Eigen::Matrix3Xd>& points, const Neighborhoods& hoods,
                    bool layered, int workers, double share) {
  const std::size_t n = hoods.size();
  // The cloud's share of T::noise_sample (a tile's of the whole cloud's), at least
  // T::least_noise_sample: the whole cloud's own sampling when share is 1.
  const std::size_t wanted =
      share >= 1.0
          ? T::noise_sample
          : std::max(
                T::least_noise_sample,
                static_cast<std::size_t>(std::ceil(static_cast<double>(T::noise_sample) * share)));
  const std::size_t stride = std::max<std::size_t>(1, n / wanted);
  const std::size_t m = (n + stride - 1) / stride;
  std::vector<SampleScale> samples(m);
#pragma omp parallel for schedule(dynamic, 256) num_threads(workers)
  for (std::size_t j = 0; j < m; ++j)
    samples[j] = sampleScale(points, hoods[j * stride], j * stride, layered);
  std::vector<double> variance, spacing, sample_variance;
  std::vector<pcl::index_t> sampled;
  for (std::size_t j = 0; j < m; ++j) {
    const SampleScale& t = samples[j];
    if (t.has_spacing)
      spacing.push_back(t.spacing);
    if (t.has_variance)
      variance.push_back(t.variance);
    if (t.spans) {
      sampled.push_back(static_cast<pcl::index_t>(j * stride));
      sample_variance.push_back(t.local_variance);
    }
  }
  DataScale out;
  out.noise = std::sqrt(quantile(variance, T::noise_quantile));
  out.spacing = quantile(std::move(spacing), 0.5);
  out.sampled = std::move(sampled);
  out.variance = std::move(sample_variance);
  return out;
}

/// Each point's σ: the noise of a sensor grows with range and lies along the ray, so that one
/// surface seen face-on carries several times the noise across it of another seen at a grazing
/// angle. The estimator of dataScale — a low quantile of the neighborhoods' variance estimates —
/// is taken locally, over the sampled neighborhoods nearest (in the neighbor graph) to each
/// sampled one, then opened (erosion and dilation over the same), and each point takes the σ of
/// the sampled point its neighbor graph reaches first. Points no sample reaches keep the global σ̂.
/// \a raised_only: the cloud's σ̂ except where a point's own σ is larger by more than
/// T::local_noise_ratio (the tolerance's model); otherwise each point's own σ.
std::vector<double> localNoise(const Neighborhoods& hoods, const DataScale& scale, std::size_t n,
                               bool raised_only) {
  // Graph distance to the samples: a breadth-first search from all of them at once; `owner` is
  // the sample that reaches a point first (ties to the earlier sample: deterministic).
  constexpr std::int32_t kNone = -1;
  std::vector<std::int32_t> owner(n, kNone);
  std::vector<pcl::index_t> queue;
  queue.reserve(n);
  for (std::size_t j = 0; j < scale.sampled.size(); ++j) {
    owner[static_cast<std::size_t>(scale.sampled[j])] = static_cast<std::int32_t>(j);
    queue.push_back(scale.sampled[j]);
  }
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const pcl::index_t i = queue[head];
    for (pcl::index_t k : hoods[static_cast<std::size_t>(i)])
      if (owner[static_cast<std::size_t>(k)] == kNone) {
        owner[static_cast<std::size_t>(k)] = owner[static_cast<std::size_t>(i)];
        queue.push_back(k);
      }
  }
  // The samples adjacent to each sample (their owned points touch): the sample graph; each
  // sample's local estimate pools the estimates of the samples nearest to it in that graph.
  const std::size_t m = scale.sampled.size();
  std::vector<std::vector<std::int32_t>> adjacent(m);
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t a = owner[i];
    if (a == kNone)
      continue;
    for (pcl::index_t k : hoods[i]) {
      const std::int32_t b = owner[static_cast<std::size_t>(k)];
      if (b != kNone && b != a)
        adjacent[static_cast<std::size_t>(a)].push_back(b);
    }
  }
  for (auto& list : adjacent) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  std::vector<double> sample_sigma(m, scale.noise);
  std::vector<std::int32_t> seen(m, -1), ring;
  // At least T::local_noise_samples samples and T::local_noise_points points: a small cloud,
  // sampled at every point, pools a patch of the same size as a large one.
  const std::size_t stride = std::max<std::size_t>(1, n / std::max<std::size_t>(1, m));
  const std::size_t pool_size =
      std::max(T::local_noise_samples, (T::local_noise_points + stride - 1) / stride);
  std::vector<double> pool;
  std::vector<std::int32_t> rings;  // each sample's ring, one after another
  std::vector<std::size_t> ring_end(m, 0);
  for (std::size_t j = 0; j < m; ++j) {
    ring.assign(1, static_cast<std::int32_t>(j));
    seen[j] = static_cast<std::int32_t>(j);
    for (std::size_t head = 0; head < ring.size() && ring.size() < pool_size; ++head)
      for (std::int32_t b : adjacent[static_cast<std::size_t>(ring[head])])
        if (seen[static_cast<std::size_t>(b)] != static_cast<std::int32_t>(j) &&
            ring.size() < pool_size) {
          seen[static_cast<std::size_t>(b)] = static_cast<std::int32_t>(j);
          ring.push_back(b);
        }
    pool.clear();
    for (std::int32_t b : ring)
      pool.push_back(scale.variance[static_cast<std::size_t>(b)]);
    sample_sigma[j] = std::sqrt(quantile(pool, T::local_noise_quantile));
    rings.insert(rings.end(), ring.begin(), ring.end());
    ring_end[j] = rings.size();
  }
  // An opening: the least σ around each sample (erosion), then the largest of those around it
  // (dilation). Noise is a property of a wide surface seen from one range; the residual of a model
  // that does not fit (a crease, a fillet too small for its neighborhoods) is a narrow band along
  // a feature, which the erosion removes and the dilation does not bring back, while a wide
  // region gets its whole extent back: a CAD part's tolerance stays the cloud's.
  auto aroundEach = [&](const std::vector<double>& in, bool least) {
    std::vector<double> out(m);
    for (std::size_t j = 0; j < m; ++j) {
      out[j] = in[j];
      for (std::size_t r = j ? ring_end[j - 1] : 0; r < ring_end[j]; ++r) {
        const double v = in[static_cast<std::size_t>(rings[r])];
        out[j] = least ? std::min(out[j], v) : std::max(out[j], v);
      }
    }
    return out;
  };
  std::vector<double> opened = aroundEach(aroundEach(sample_sigma, true), false);
  sample_sigma = std::move(opened);
  // The simpler model unless the data demand the other: one σ for the cloud, raised where a
  // point's own is more than T::local_noise_ratio times larger, and by more than the tolerance's
  // floor (noise-free data: σ̂ ≈ 0, and any residual of a model that does not fit is a large
  // ratio). Never lowered: where the noise is below σ̂ (a surface seen at a grazing angle) the
  // tolerance keeps the cloud's, as before.
  std::vector<double> sigma(n, scale.noise);
  for (std::size_t i = 0; i < n; ++i)
    if (owner[i] != kNone) {
      const double local = sample_sigma[static_cast<std::size_t>(owner[i])];
      if (!raised_only ||
          (local > T::local_noise_ratio * scale.noise &&
           T::noise_factor * (local - scale.noise) > T::spacing_factor * scale.spacing))
        sigma[i] = local;
    }
  return sigma;
}

/// The median of the local steps of \a lattice at evenly strided points (at most T::noise_sample).
double medianStep(const QuantizedAxis& lattice, const Eigen::Ref<const Eigen::Matrix3Xd>& points) {
  const auto n = static_cast<std::size_t>(points.cols());
  const std::size_t stride = std::max<std::size_t>(1, n / T::noise_sample);
  std::vector<double> steps;
  for (std::size_t i = 0; i < n; i += stride)
    steps.push_back(lattice.stepAt(points.col(static_cast<Eigen::Index>(i))));
  return quantile(std::move(steps), 0.5);
}

}  // namespace

void estimateScale(SegmentationState& s) {
  // A coordinate recorded on levels (Kinect-like depth) puts a point up to half a step off its
  // surface along that axis, and a disparity sensor's noise grows with depth as its step does
  // (about half a step): each point's tolerance adds T::step_factor local steps to the tolerance
  // from the noise and spacing.
  s.result.lattice = detectQuantizedAxis(s.points);
  DataScale scale = dataScale(s.points, s.hoods, s.result.lattice.detected(), s.workers(),
                              s.parameters.noise_sample_share);
  // Levels finer than the noise (depth stored in millimetres under centimetres of noise) are
  // part of it, not a sensor's levels to model: their rounding adds (q / √12)² to the variance.
  if (s.result.lattice.detected() &&
      medianStep(s.result.lattice, s.points) < T::fine_levels * scale.noise) {
    s.result.lattice = QuantizedAxis{};
    scale = dataScale(s.points, s.hoods, false, s.workers(), s.parameters.noise_sample_share);
  }
  s.result.step_factor = s.result.lattice.detected() ? T::step_factor : 0.0;
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
  // Each point's own noise in place of the cloud's (localNoise), on a noisy cloud: where σ̂ is
  // below a twentieth of the spacing (CAD parts, meshes, noise-free samples) the residuals that
  // vary over the cloud are model error — a thin wall's two sheets, a crease — not a sensor's
  // noise. Depth on levels has its own per-point model (the local step).
  if (!s.parameters.distance && !s.result.lattice.detected() &&
      scale.noise >= T::spacing_factor * scale.spacing) {
    s.noise = localNoise(s.hoods, scale, s.n, true);
    for (std::size_t i = 0; i < s.n; ++i)
      tolerance[i] += T::noise_factor * (s.noise[i] - scale.noise);
    s.result.noise_range = {quantile(s.noise, 0.05), quantile(s.noise, 0.95)};
  }
  // The merge (acceptsUnion) asks whether one primitive explains two regions within their noise.
  // On depth recorded on levels the tolerance keeps its model (the local step), but each point's
  // σ is its own: the widened neighborhoods span the levels, so their residual is the sensor's
  // noise and rounding together, which grow with depth (about a third of the local step at 2 m on
  // the simulated Kinect). A sensor's frame: depth on levels, or a view the caller says is a
  // sensor's (a LiDAR scan has no levels, and its noise alone does not tell it from a sparse CAD
  // part).
  s.sensor_frame =
      !s.parameters.distance && (s.result.lattice.detected() || s.parameters.sensor_view);
  if (!s.parameters.distance && s.noise.empty())
    s.noise = s.result.lattice.detected() ? localNoise(s.hoods, scale, s.n, false)
                                          : std::vector<double>(s.n, scale.noise);
  s.result.min_points = s.parameters.min_points.value_or(T::default_min_points);
  s.result.labels.assign(s.n, -1);
  s.grower.emplace(s.points, s.normals, s.hoods, std::move(tolerance), s.result.max_angle);
  s.tried.assign(s.n, 0);
}

}  // namespace slipfit::phases
