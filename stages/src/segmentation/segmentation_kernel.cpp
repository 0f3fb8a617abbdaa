#include "slipfit/segmentation/segmentation_kernel.h"

#include "slipfit/core/exceptions.h"
#include "slipfit/fitting/model_selection.h"
#include "slipfit/neighborhoods/depth_quantization.h"
#include "slipfit/segmentation/crease_fillet.h"

#include <omp.h>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <tuple>

namespace slipfit {

namespace {

// The default tolerance: 3 σ of the estimated noise (a Gaussian keeps 99.7 % of its points) plus
// a twentieth of the spacing, the floor for noise-free data (CAD: σ ≈ 0), where it admits float
// rounding and the sagitta of fits made on part of a region while it grows.
constexpr double kNoiseFactor = 3.0;
constexpr double kSpacingFactor = 0.05;
// Steps of a quantized axis added to a point's tolerance: see estimateScale.
constexpr double kStepFactor = 2.0;
// The default smallest segment: an absolute count (a fraction of N starves the small shapes of a
// large scene); small faces of CAD parts have 20–60 points.
constexpr std::size_t kDefaultMinPoints = 20;
// Between a surface's RMS distance (≈ 0.33 ε) and that of a slab filled at random (0.58 ε).
constexpr double kVolumeRatio = 0.45;
// reviseTypes: a wide region's type is revisited when a candidate's median normal angle is less
// than this fraction of its own primitive's (its normals turn beyond their noise).
constexpr double kNormalTurnRatio = 2.0;
// A region this many times the size of another dominates their union's fit (mergeRegions) and
// may absorb it (absorbFragments).
constexpr std::size_t kDominates = 4;
// absorbFragments: passes, each on the regions the one before left (a speck that touched only
// another speck can join the region that absorbed it).
constexpr int kAbsorbPasses = 4;
// refineBoundaries: a boundary moves a ring of points per pass; eight passes cross the band a
// plane takes off a tangent fillet at the 1 M-point scenes' density.
constexpr int kBoundaryPasses = 8;
// refineBoundaries: how much lower (in squared standard units) another primitive's cost must be
// for a point within the noise of both to move: 4, a likelihood ratio of e² ≈ 7.
constexpr double kStayCost = 4.0;
// refineBoundaries: after two passes, a pass runs while it moves fewer than this share of the
// points the one before moved.
constexpr double kSettling = 0.5;
// refineBoundaries: two distances within this share of the point's tolerance (2σ̂ of its 3σ̂, and
// as much of its depth steps) are a tie the neighborhood decides.
constexpr double kTieShare = 2.0 / 3.0;
// recoverSmallFaces: the fewest free points tried as a face (a plane needs 3, and 3 per parameter
// must hold), and the share of them its fit must hold.
constexpr std::size_t kSmallestPatch = 8;
constexpr double kHeld = 0.8;
// recoverSmallFaces: a face whose points lie further apart than this many times the points of the
// faces around it is points scattered through the volume, not a surface sampled like its
// surroundings. Points sampled at random on a surface with density ρ are a median 0.47/√ρ from
// their nearest; twice that is a surface sampled a quarter as densely as its surroundings.
constexpr double kScattered = 2.0;
// growFreeSeeds: a gap this many tolerances wide between the offsets of a seed's 2-ring along its
// normal divides two sheets of a thin wall. The tolerance is 3 σ̂ (plus a twentieth of the
// spacing): a gap of 12 σ̂ between neighbouring offsets of one noisy surface does not occur.
constexpr double kSheetGap = 4.0;
// recoverFillets: the parameters a fillet adds (a cylinder's five) in the BIC, and the most points
// its radius is chosen on.
constexpr double kFilletParameters = 5.0;
constexpr std::size_t kFilletSample = 4000;

double quantile(std::vector<double> v, double q) {
  if (v.empty())
    return 0.0;
  auto at = v.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), at, v.end());
  return *at;
}

/// The median distance from each of \a set to its nearest other point (0 for an empty set).
double medianNearestDistance(const Neighborhoods& hoods, const std::vector<int>& set) {
  std::vector<double> d;
  d.reserve(set.size());
  for (int i : set) {
    const NeighborView v = hoods[static_cast<std::size_t>(i)];
    if (v.size() > 1)
      d.push_back(std::sqrt(static_cast<double>(v.sqr_distances[1])));
  }
  return d.empty() ? 0.0 : quantile(std::move(d), 0.5);
}

/// The median distance from each of \a set to its nearest other member of the set (those whose
/// \a stamp is \a mark) among its neighbors; a point with none among them is not sampled with
/// the set (+inf): an outlier whose nearest are all points of a surface nearby.
double medianNearestWithin(const Neighborhoods& hoods, const std::vector<int>& set,
                           const std::vector<std::uint32_t>& stamp, std::uint32_t mark) {
  std::vector<double> d;
  d.reserve(set.size());
  for (int i : set) {
    const NeighborView v = hoods[static_cast<std::size_t>(i)];
    if (v.size() < 2)
      continue;
    std::size_t j = 1;
    while (j < v.size() && stamp[static_cast<std::size_t>(v[j])] != mark)
      ++j;
    d.push_back(j < v.size() ? std::sqrt(static_cast<double>(v.sqr_distances[j]))
                             : std::numeric_limits<double>::infinity());
  }
  return d.empty() ? 0.0 : quantile(std::move(d), 0.5);
}

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

/// Two sheets of a neighborhood: which of its points lie on the upper one, and how far apart the
/// sheets' means lie along their common normal against the points' RMS distance off them.
struct SheetSplit {
  std::vector<char> upper;
  double separation = 0.0;
  double rms = 0.0;
};

/// Splits the points \a idx in two sheets by alternating, from the start \a axis: split the
/// offsets along the axis at their widest gap (at least kSheetPoints each side), then take as the
/// axis the least principal direction of the two groups about their own means.
SheetSplit splitSheets(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                       const std::vector<pcl::index_t>& idx, Eigen::Vector3d axis) {
  constexpr std::size_t kSheetPoints = 2;
  const std::size_t k = idx.size();
  SheetSplit split;
  split.upper.assign(k, 0);
  std::vector<std::pair<double, std::size_t>> offset(k);
  for (int pass = 0; pass < 3; ++pass) {
    for (std::size_t j = 0; j < k; ++j)
      offset[j] = {axis.dot(points.col(idx[j])), j};
    std::sort(offset.begin(), offset.end());
    std::size_t cut = kSheetPoints;  // the upper group starts here
    for (std::size_t j = kSheetPoints; j + kSheetPoints <= k; ++j)
      if (offset[j].first - offset[j - 1].first > offset[cut].first - offset[cut - 1].first)
        cut = j;
    for (std::size_t j = 0; j < k; ++j)
      split.upper[offset[j].second] = j >= cut ? 1 : 0;
    Eigen::Vector3d mean[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
    for (std::size_t j = 0; j < k; ++j)
      mean[split.upper[j] ? 1 : 0] += points.col(idx[j]);
    mean[0] /= static_cast<double>(cut);
    mean[1] /= static_cast<double>(k - cut);
    Eigen::Matrix3d within = Eigen::Matrix3d::Zero();
    for (std::size_t j = 0; j < k; ++j) {
      const Eigen::Vector3d d = points.col(idx[j]) - mean[split.upper[j] ? 1 : 0];
      within += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(within);
    axis = eigen.eigenvectors().col(0);
    split.separation = std::abs(axis.dot(mean[1] - mean[0]));
    split.rms = std::sqrt(std::max(0.0, eigen.eigenvalues()(0)) / static_cast<double>(k));
  }
  return split;
}

/// The points of the neighborhood \a idx on point \a i's own sheet when it holds two sheets of a
/// thin wall (a wall about as thick as the spacing puts both faces in every neighborhood);
/// otherwise \a idx itself. splitSheets starts from each principal axis of the neighborhood
/// (\a axes; with a dozen points a neighborhood is barely wider than the wall, and its least axis
/// may lie along it) and the split whose sheets lie furthest apart for their RMS counts. Two
/// sheets: their means lie apart by more than kSheetSeparation times the RMS and a tenth of the
/// neighborhood's radius \a radius. One noisy surface split in two leaves its halves 2.7 RMS
/// apart; faces meeting at a crease share no normal, and their RMS off it is large.
std::vector<pcl::index_t> ownSheet(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                   const std::vector<pcl::index_t>& idx, pcl::index_t i,
                                   const Eigen::Matrix3d& axes, double radius) {
  constexpr double kSheetSeparation = 20.0;
  const std::size_t k = idx.size();
  const auto at = std::find(idx.begin(), idx.end(), i);
  if (k < 8 || at == idx.end())
    return idx;
  SheetSplit best;
  for (int a = 0; a < 3; ++a) {
    SheetSplit split = splitSheets(points, idx, axes.col(a));
    if (best.upper.empty() || split.separation * best.rms > best.separation * split.rms)
      best = std::move(split);
  }
  if (!(best.separation > kSheetSeparation * best.rms && best.separation > 0.1 * radius))
    return idx;
  const char own = best.upper[static_cast<std::size_t>(at - idx.begin())];
  std::vector<pcl::index_t> sheet;
  for (std::size_t j = 0; j < k; ++j)
    if (best.upper[j] == own)
      sheet.push_back(idx[j]);
  return sheet;
}

/// \a layered: the cloud's depth is recorded on levels (detectQuantizedAxis), whose layers in a
/// neighborhood are part of its spread, not sheets of a thin wall.
DataScale dataScale(const Eigen::Ref<const Eigen::Matrix3Xd>& points, const Neighborhoods& hoods,
                    bool layered) {
  std::vector<double> variance, spacing;
  const std::size_t n = hoods.size();
  const std::size_t stride = std::max<std::size_t>(1, n / 20000);  // a sample is enough
  constexpr double kQuantile = 0.25, kQuantileZ = -0.6744897501960817;
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
    variance.push_back(rss / nu / chiSquareQuantileOverDof(nu, kQuantileZ));
  }
  return {std::sqrt(quantile(std::move(variance), kQuantile)), quantile(std::move(spacing), 0.5)};
}

/// Two planes more than the angle tolerance apart: their union is no plane, and merging them is a
/// claim that they are facets of one curved surface.
bool isCrease(const Primitive& a, const Primitive& b, double max_angle) {
  const auto* pa = std::get_if<Plane>(&a);
  const auto* pb = std::get_if<Plane>(&b);
  return pa && pb && std::abs(pa->normal.dot(pb->normal)) < std::cos(max_angle);
}

/// The segment's own slippage verdict, and its primitive as a second start of the refinement,
/// which weighs the members by their \a precision as the final fit does (a start refined with
/// equal weights would undo that weighting on a quantized scan).
void refineFromSlippage(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                        const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                        const Eigen::VectorXd& precision, Segment& s) {
  const auto m = static_cast<Eigen::Index>(s.indices.size());
  Eigen::Matrix3Xd p(3, m), n(3, m);
  for (Eigen::Index j = 0; j < m; ++j) {
    p.col(j) = points.col(s.indices[static_cast<std::size_t>(j)]);
    n.col(j) = normals.col(s.indices[static_cast<std::size_t>(j)]);
  }
  s.slippage = analyzeSlippage(p, n, Eigen::VectorXd::Ones(m));
  if (!s.slippage->primitive || typeOf(*s.slippage->primitive) != s.fit.type)
    return;
  const Primitive start = refinePrimitive(*s.slippage->primitive, p, precision, 100);
  const double loss = weightedLoss(p, precision, start);
  if (loss < weightedLoss(p, precision, s.fit.refined)) {
    s.fit.refined = start;
    s.fit.loss_refined = loss;
  }
}

double rmsOf(const Eigen::Ref<const Eigen::Matrix3Xd>& points, const std::vector<int>& members,
             const Primitive& primitive, double* max_distance) {
  double sum = 0.0, worst = 0.0;
  for (int i : members) {
    const double d = distance(points.col(i), primitive);
    sum += d * d;
    worst = std::max(worst, d);
  }
  if (max_distance)
    *max_distance = worst;
  return members.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(members.size()));
}

/// Each point of \a set gets in \a own the normal of its neighbors within the set (itself and at
/// least three others, \a known set; else the cloud's normal, \a known cleared): at a face a few
/// rows wide every neighborhood straddles its edges, and normals estimated over them lead the
/// closed forms astray (a hole's wall fitted as a cylinder from such normals left an RMS of a fifth
/// of its radius).
void estimateOwnNormals(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                        const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                        const Neighborhoods& hoods, const std::vector<int>& set,
                        std::vector<std::uint32_t>& stamp, std::uint32_t generation,
                        Eigen::Matrix3Xd& own, std::vector<char>& known) {
  for (int i : set)
    stamp[static_cast<std::size_t>(i)] = generation;
  for (int i : set) {
    Eigen::Vector3d mean = points.col(i);
    Eigen::Matrix3d second = points.col(i) * points.col(i).transpose();
    int count = 1;
    for (pcl::index_t j : hoods[static_cast<std::size_t>(i)])
      if (j != i && stamp[static_cast<std::size_t>(j)] == generation) {
        mean += points.col(j);
        second += points.col(j) * points.col(j).transpose();
        ++count;
      }
    own.col(i) = normals.col(i);
    known[static_cast<std::size_t>(i)] = count >= 4;
    if (count < 4)
      continue;
    mean /= count;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(second / count -
                                                               mean * mean.transpose());
    own.col(i) = eigen.eigenvectors().col(0);
  }
}

/// The points of \a candidates on the seed's own sheet of a thin wall: ordered by their offset
/// along the seed's \a normal, the run around the seed that no gap wider than \a gap interrupts.
/// Empty when no such gap divides the candidates (one surface, or faces meeting at a crease:
/// their offsets run on without a gap). A wall about as thick as the spacing puts both of its
/// sheets in every neighborhood; the normal is still the sheets' (they are parallel), but no
/// primitive fits both.
std::vector<int> seedSheet(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                           const Eigen::Vector3d& normal, int seed,
                           const std::vector<int>& candidates, double gap) {
  std::vector<std::pair<double, int>> offset;  // (offset, index), the seed at 0
  offset.reserve(candidates.size() + 1);
  offset.emplace_back(0.0, seed);
  for (int j : candidates)
    if (j != seed)
      offset.emplace_back(normal.dot(points.col(j) - points.col(seed)), j);
  std::sort(offset.begin(), offset.end());
  const auto at = static_cast<std::size_t>(
      std::find_if(offset.begin(), offset.end(), [&](const auto& o) { return o.second == seed; }) -
      offset.begin());
  std::size_t lo = at;
  std::size_t hi = at;
  while (lo > 0 && offset[lo].first - offset[lo - 1].first <= gap)
    --lo;
  while (hi + 1 < offset.size() && offset[hi + 1].first - offset[hi].first <= gap)
    ++hi;
  if (lo == 0 && hi + 1 == offset.size())
    return {};
  std::vector<int> sheet;
  for (std::size_t k = lo; k <= hi; ++k)
    sheet.push_back(offset[k].second);
  std::sort(sheet.begin(), sheet.end());
  return sheet;
}

/// The simplest adequate primitive of the points \a set with the normals \a own (an evenly
/// strided RegionGrower::kTypeSubset of them decide, as in RegionGrower::fitBest).
FitResult fitSet(const Eigen::Ref<const Eigen::Matrix3Xd>& points, const Eigen::Matrix3Xd& own,
                 const std::vector<int>& set) {
  const std::size_t stride = std::max<std::size_t>(1, set.size() / RegionGrower::kTypeSubset);
  std::vector<int> subset;
  for (std::size_t k = 0; k < set.size(); k += stride)
    subset.push_back(set[k]);
  return fitAuto(points(Eigen::all, subset), own(Eigen::all, subset),
                 Eigen::VectorXd::Ones(static_cast<Eigen::Index>(subset.size())));
}

}  // namespace

SegmentationKernel::SegmentationKernel(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                       const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                                       const Neighborhoods& neighborhoods,
                                       const std::vector<SlippageType>& local_types,
                                       const SegmentationParameters& parameters)
    : points_(points),
      normals_(normals),
      hoods_(neighborhoods),
      local_types_(local_types),
      parameters_(parameters),
      n_(static_cast<std::size_t>(points.cols())) {
  parameters_.validate();
  if (n_ == 0)
    throw DegenerateInputError("segmentation: the cloud is empty");
  if (static_cast<std::size_t>(normals.cols()) != n_ || hoods_.size() != n_ ||
      local_types_.size() != n_)
    throw DegenerateInputError(
        "segmentation: points, normals, neighborhoods and local types differ in number");
  if (!normals.allFinite())
    throw DegenerateInputError("segmentation: some normals are missing (NaN)");
}

void SegmentationKernel::estimateScale() {
  // A coordinate recorded on levels (Kinect-like depth) puts a point up to half a step off its
  // surface along that axis, and a disparity sensor's noise grows with depth as its step does
  // (about half a step): each point's tolerance adds kStepFactor local steps to the tolerance
  // from the noise and spacing.
  result_.lattice = detectQuantizedAxis(points_);
  result_.step_factor = result_.lattice.detected() ? kStepFactor : 0.0;
  const DataScale scale = dataScale(points_, hoods_, result_.lattice.detected());
  // Distances closer than the floor of noise-free data (a twentieth of the spacing) cannot tell
  // two primitives apart: see shareEdges.
  edge_margin_ = kSpacingFactor * scale.spacing;
  spacing_ = scale.spacing;
  result_.noise = scale.noise;
  result_.noise_factor = parameters_.distance ? 0.0 : kNoiseFactor;
  result_.distance =
      parameters_.distance.value_or(kNoiseFactor * scale.noise + kSpacingFactor * scale.spacing);
  if (!(result_.distance > 0.0))
    throw DegenerateInputError(
        "segmentation: cannot derive a distance tolerance (all points coincide); set distance");
  result_.max_angle = parameters_.max_angle;
  std::vector<double> tolerance(n_);
  for (std::size_t i = 0; i < n_; ++i)
    tolerance[i] = result_.tolerance(points_.col(static_cast<Eigen::Index>(i)));
  result_.min_points = parameters_.min_points.value_or(kDefaultMinPoints);
  result_.labels.assign(n_, -1);
  grower_.emplace(points_, normals_, hoods_, std::move(tolerance), result_.max_angle);
  tried_.assign(n_, 0);
}

// Grows one region from \a members (a seed's neighborhood) with \a type; keeps it when it reaches
// min_points. \a seed_type is reported with the segment. With \a type_chosen (the type is already
// the simplest adequate one of the seed's neighborhood) a region that grows to fewer than
// min_points is dropped at once, without trying the other types.
void SegmentationKernel::growRegion(PrimitiveType type, std::vector<int> members,
                                    SlippageType seed_type, bool type_chosen) {
  RegionGrower& grower = *grower_;
  if (static_cast<int>(members.size()) < minimumPoints(type) + 2)
    return;
  FitResult fit = grower.fit(type, members);
  if (!fit.ok())
    return;
  grower.prune(members, fit.refined);
  if (members.empty())
    return;
  ++result_.regions_grown;
  fit = grower.grow(type, members, std::move(fit), result_.labels);
  if (type_chosen && members.size() < result_.min_points) {
    for (int i : members)
      tried_[static_cast<std::size_t>(i)] = 1;
    return;
  }
  // The seed's local type can be wrong (a cone patch reads as a cylinder): refit the grown region
  // with the best type and, if it changes, grow again from the region with that type. The local
  // evidence stands unless another type fits clearly better, by the median distance (a BIC
  // margin, or the RMS, lets a wide sphere absorb the crease points of a plane).
  const double current = grower.medianDistance(members, fit.refined);
  FitResult best;
  if (current > result_.noise)  // a Gaussian's median |d| is 0.67 σ: this model explains the data
    best = grower.fitBest(members);
  if (current > result_.noise && best.ok() && best.type != type &&
      grower.medianDistance(members, best.refined) < 0.75 * current) {
    grower.prune(members, best.refined);
    if (!members.empty())
      fit = grower.grow(best.type, members, std::move(best), result_.labels);
  }
  FitResult final_fit = grower.fit(fit.type, members);
  if (final_fit.ok())
    fit = std::move(final_fit);
  grower.prune(members, fit.refined);
  for (int i : members)
    tried_[static_cast<std::size_t>(i)] = 1;
  if (members.size() < result_.min_points)
    return;
  // The seed's type fitted in its simpler limit (a cone of 0.06° whose apex lies 10⁴ sizes away
  // is a cylinder; isNearlyDegenerate) gives way to the simplest adequate type.
  if (fit.type != PrimitiveType::plane &&
      isNearlyDegenerate(fit.refined, points_(Eigen::all, members))) {
    const FitResult simpler = grower.fitBest(members);
    FitResult refit = simpler.ok() ? grower.fit(simpler.type, members) : FitResult{};
    if (refit.ok())
      fit = std::move(refit);
  }
  addRegion(std::move(members), std::move(fit), seed_type);
}

void SegmentationKernel::addRegion(std::vector<int> members, FitResult fit,
                                   SlippageType seed_type) {
  const auto label = static_cast<std::int32_t>(regions_.size());
  for (int i : members)
    result_.labels[static_cast<std::size_t>(i)] = label;
  regions_.push_back(std::move(members));
  fits_.push_back(std::move(fit));
  seed_types_.push_back(seed_type);
  alive_.push_back(1);
}

void SegmentationKernel::growSlippageSeeds() {
  // Seeds: points whose neighbors agree with their own primitive type, most agreement first
  // (ties by index: deterministic), grown with that type.
  std::vector<std::pair<int, int>> seeds;  // (−agreement, index)
  for (std::size_t i = 0; i < n_; ++i) {
    if (!primitiveTypeOf(local_types_[i]))
      continue;
    int agree = 0;
    for (pcl::index_t j : hoods_[i])
      agree += local_types_[static_cast<std::size_t>(j)] == local_types_[i] ? 1 : 0;
    if (2 * agree > static_cast<int>(hoods_[i].size()))
      seeds.emplace_back(-agree, static_cast<int>(i));
  }
  std::sort(seeds.begin(), seeds.end());
  for (const auto& [neg_agree, seed] : seeds) {
    const auto us = static_cast<std::size_t>(seed);
    if (result_.labels[us] >= 0 || tried_[us])
      continue;
    std::vector<int> members;
    for (pcl::index_t j : hoods_[us])
      if (result_.labels[static_cast<std::size_t>(j)] < 0 &&
          local_types_[static_cast<std::size_t>(j)] == local_types_[us])
        members.push_back(j);
    tried_[us] = 1;
    growRegion(*primitiveTypeOf(local_types_[us]), std::move(members), local_types_[us], false);
  }
}

void SegmentationKernel::growFreeSeeds() {
  // What is left — small faces whose neighborhoods straddle an edge, so that no point has an
  // agreeing local type — is seeded from every unlabelled point in index order, with the simplest
  // adequate type of its unlabelled neighbors.
  RegionGrower& grower = *grower_;
  std::fill(tried_.begin(), tried_.end(), 0);
  // Outliers scattered through the volume have free neighborhoods too: a seed's must be sampled
  // like the regions of the first round around it (THEORY §6 step 8b).
  const std::vector<double> seeded_spacing = regionSpacings();
  std::vector<std::uint32_t> stamp(n_, 0);
  std::uint32_t generation = 0;
  for (std::size_t us = 0; us < n_; ++us) {
    if (result_.labels[us] >= 0 || tried_[us])
      continue;
    tried_[us] = 1;
    std::vector<int> members;
    for (pcl::index_t j : hoods_[us])
      if (result_.labels[static_cast<std::size_t>(j)] < 0)
        members.push_back(j);
    if (4 * members.size() < 3 * hoods_[us].size())
      continue;  // a point at the crease of a grown segment, not a face of its own
    // A quick look with the closed forms first (outliers fail it by far), then the refined fits.
    const double seed_tolerance = grower.tolerance(static_cast<int>(us));
    auto fitSeed = [&](const std::vector<int>& set) {
      const FitResult quick = grower.fitBest(set, false);
      return quick.ok() && quick.rms_distance > seed_tolerance &&
                     quick.rms_distance <= 3.0 * seed_tolerance
                 ? grower.fitBest(set)
                 : quick;
    };
    FitResult start = fitSeed(members);
    // The free 2-ring: the seed's free neighbors and theirs.
    std::vector<int> ring2;
    for (int m : members)
      for (pcl::index_t j : hoods_[static_cast<std::size_t>(m)])
        if (result_.labels[static_cast<std::size_t>(j)] < 0)
          ring2.push_back(j);
    std::sort(ring2.begin(), ring2.end());
    ring2.erase(std::unique(ring2.begin(), ring2.end()), ring2.end());
    if (!(start.ok() && start.rms_distance <= seed_tolerance)) {
      // A thin wall: the seed's sheet of the 2-ring, apart from the other sheet by a gap no noise
      // opens (kSheetGap tolerances), is the seed's neighborhood.
      std::vector<int> sheet = seedSheet(points_, normals_.col(static_cast<Eigen::Index>(us)),
                                         static_cast<int>(us), ring2, kSheetGap * seed_tolerance);
      if (sheet.size() >= kSmallestPatch) {
        FitResult on_sheet = fitSeed(sheet);
        if (on_sheet.ok() && on_sheet.rms_distance <= seed_tolerance) {
          start = std::move(on_sheet);
          members = std::move(sheet);
        }
      }
    }
    // The fit must also hold three points per parameter among the free 2-ring: a torus fits any
    // dozen outliers, but not the points around them.
    bool holds = start.ok() && start.rms_distance <= seed_tolerance;
    if (holds) {
      std::size_t held = 0;
      for (int j : ring2)
        held += grower.accepts(j, start.refined) ? 1 : 0;
      holds = held >= 3 * static_cast<std::size_t>(parameterCount(start.type));
    }
    if (holds)
      holds = !isScattered(members, seeded_spacing, stamp, generation);
    if (!holds) {
      // No surface here (outliers, or an edge): none of these points seeds again.
      for (int j : members)
        tried_[static_cast<std::size_t>(j)] = 1;
      continue;
    }
    growRegion(start.type, std::move(members), local_types_[us], true);
  }
}

std::optional<FitResult> SegmentationKernel::tryMerge(std::size_t a, std::size_t b) const {
  // A region four times the other's size dominates the union's fit: its primitive must then
  // hold most of the other's points already.
  const RegionGrower& grower = *grower_;
  const std::size_t big = regions_[a].size() >= regions_[b].size() ? a : b;
  const std::size_t small = big == a ? b : a;
  if (regions_[big].size() >= kDominates * regions_[small].size()) {
    std::size_t held = 0;
    for (int i : regions_[small])
      held += grower.near(i, fits_[big].refined) ? 1 : 0;
    if (2 * held < regions_[small].size())
      return std::nullopt;
  }
  std::vector<int> both = regions_[a];
  both.insert(both.end(), regions_[b].begin(), regions_[b].end());
  return grower.fitBest(both);
}

void SegmentationKernel::mergeRegions() {
  // Merge adjacent regions while the best fit of their union (any type: bands of a cone grown as
  // cylinders merge into the cone) is about as good as the parts.
  mergeAdjacent(false);
}

void SegmentationKernel::mergeSettledRegions() {
  // Boundaries and creases have settled: regions that the free crease points kept apart now touch.
  // Two adjacent regions merge when one primitive of the larger's type is the better model of
  // their union by BIC (unionIsSimpler). Not by the first merge's margin on the RMS: here, that
  // merged distinct shapes meeting at a crease (seed 6 of the 100k scenes at σ 0.5 %: 0.951 →
  // 0.929), and a plane took outlier specks one by one, each raising its RMS enough to admit the
  // next. Not into a new type: the union of a far office wall, bent by the sensor, and a strip
  // beside it was a sphere of radius 17.5 m.
  mergeAdjacent(true);
}

bool SegmentationKernel::unionIsSimpler(std::size_t a, std::size_t b,
                                        const FitResult& joint) const {
  const std::size_t larger = regions_[a].size() >= regions_[b].size() ? a : b;
  const std::size_t smaller = larger == a ? b : a;
  if (joint.type != fits_[larger].type)
    return false;
  // Each region at its own primitive against both at the joint one (BIC, jointModelIsBetter).
  // Below the floor of noise-free data (edge_margin_ per point) distances do not count.
  const auto squares = [&](const std::vector<int>& members, const Primitive& primitive) {
    const double rms = rmsOf(points_, members, primitive, nullptr);
    return static_cast<double>(members.size()) * (rms * rms + edge_margin_ * edge_margin_);
  };
  std::vector<int> both = regions_[a];
  both.insert(both.end(), regions_[b].begin(), regions_[b].end());
  const double separate =
      squares(regions_[a], fits_[a].refined) + squares(regions_[b], fits_[b].refined);
  return jointModelIsBetter(squares(both, joint.refined), separate, both.size(),
                            parameterCount(fits_[smaller].type));
}

void SegmentationKernel::mergeAdjacent(bool settled) {
  std::vector<int> version(regions_.size(), 0);
  std::set<std::tuple<std::size_t, std::size_t, int, int>> failed;
  for (bool merged = true; merged;) {
    merged = false;
    // Ordered pairs (a < b, a's points having b's among their neighbors): deterministic.
    std::vector<std::pair<std::size_t, std::size_t>> adjacent;
    const std::vector<std::set<std::size_t>> touching = touchingRegions();
    for (std::size_t a = 0; a < touching.size(); ++a)
      for (const std::size_t b : touching[a])
        if (b > a)
          adjacent.emplace_back(a, b);
    // The unions' fits, tried in parallel on the regions as they are now; a pair whose regions
    // change before its turn below is fitted again then (the same result as one at a time).
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    for (const auto& [a, b] : adjacent)
      if (!failed.count(std::make_tuple(a, b, version[a], version[b])))
        pairs.emplace_back(a, b);
    std::vector<std::optional<FitResult>> tried(pairs.size());
    const int workers = parameters_.threads > 0 ? parameters_.threads : omp_get_num_procs();
#pragma omp parallel for schedule(dynamic, 1) num_threads(workers)
    for (std::size_t k = 0; k < pairs.size(); ++k)
      tried[k] = tryMerge(pairs[k].first, pairs[k].second);
    const std::vector<int> round_version = version;
    std::size_t next = 0;
    for (const auto& [a, b] : adjacent) {
      if (!alive_[a] || !alive_[b])
        continue;
      const auto key = std::make_tuple(a, b, version[a], version[b]);
      if (failed.count(key))
        continue;  // tried before, neither has changed since
      while (next < pairs.size() && pairs[next] < std::make_pair(a, b))
        ++next;
      std::optional<FitResult> union_fit =
          next < pairs.size() && pairs[next] == std::make_pair(a, b) &&
                  version[a] == round_version[a] && version[b] == round_version[b]
              ? std::move(tried[next])
              : tryMerge(a, b);
      if (!union_fit) {
        failed.insert(key);
        continue;
      }
      FitResult fit = std::move(*union_fit);
      // Planes meeting at a crease merge only when one curved primitive explains their union
      // better than either plane explains its own points: the facets of a wide fillet whose
      // sagitta over each is within ε (on the 1 M-point scenes, seed 24: 0.940 → 0.949); two
      // faces of a box never do. Other pairs merge while the union's fit is about as good.
      const bool crease = isCrease(fits_[a].refined, fits_[b].refined, result_.max_angle);
      const double limit = crease ? std::min(fits_[a].rms_distance, fits_[b].rms_distance)
                                  : parameters_.merge_factor *
                                        std::max(fits_[a].rms_distance, fits_[b].rms_distance);
      const bool accepted =
          fit.ok() && (settled ? unionIsSimpler(a, b, fit) : fit.rms_distance <= limit);
      if (!accepted) {
        failed.insert(key);
        continue;
      }
      ++version[a];
      for (int i : regions_[b])
        result_.labels[static_cast<std::size_t>(i)] = static_cast<std::int32_t>(a);
      regions_[a].insert(regions_[a].end(), regions_[b].begin(), regions_[b].end());
      regions_[b].clear();
      fits_[a] = std::move(fit);
      alive_[b] = 0;
      ++result_.merges;
      merged = true;
    }
  }
}

void SegmentationKernel::reviseTypes() {
  // A region's type is chosen on its own points. Between two planes joined by a tangent fillet the
  // planes take the fillet's first rows on either side (they lie within ε of them), and the band
  // left in the middle can be nearly flat at the noise: a plane, which then keeps the rows. A
  // narrow region — fewer points of its own than of other regions within two rings of it — cannot
  // decide its type alone, so its type is revisited on the points it contests: every other type
  // fitted to the region that explains the region's own points adequately (RMS within
  // kAdequacyMargin of the current type's) and is not in a flat limit is scored on those
  // contested points, each at its squared distance (capped at its tolerance) to the nearer of its
  // own primitive and the candidate, where the candidate accepts it. The candidate replaces the
  // region's primitive when that sum plus its parameters' cost (BIC: p σ² ln n, σ² the noise plus
  // the floor of noise-free data) is below the current type's and it takes at least 3 points per
  // parameter; refineBoundaries then moves the points. Wide regions keep their type: an office
  // wall tried so became a cylinder by taking the rims of its neighbors. On the 1 M-point scenes
  // this raised the mean IoU by 0.003–0.006 (seeds 11, 24, 26) and left the 100k scenes and
  // Fit4CAD unchanged; tests/stages/segmentation/segmentation_kernel_test.cpp has the brackets.
  RegionGrower& grower = *grower_;
  const double sigma2 = result_.noise * result_.noise + edge_margin_ * edge_margin_;
  const auto medianAngle = [&](const std::vector<int>& members, const Primitive& primitive) {
    std::vector<double> angles;
    for (std::size_t m = 0; m < members.size(); m += 1 + members.size() / 512)
      angles.push_back(normalAngle(members[m], primitive));
    return quantile(angles, 0.5);
  };
  std::vector<std::uint32_t> stamp(n_, 0);
  std::uint32_t generation = 0;
  for (std::size_t r = 0; r < regions_.size(); ++r) {
    if (!alive_[r] || regions_[r].size() < result_.min_points)
      continue;
    const std::vector<int>& members = regions_[r];
    const auto own = static_cast<std::int32_t>(r);
    // The contested points: other regions' points within two rings of the region.
    ++generation;
    std::vector<int> ring;
    for (int i : members)
      for (pcl::index_t j : hoods_[static_cast<std::size_t>(i)]) {
        const auto uj = static_cast<std::size_t>(j);
        if (result_.labels[uj] >= 0 && result_.labels[uj] != own && stamp[uj] != generation) {
          stamp[uj] = generation;
          ring.push_back(j);
        }
      }
    if (ring.empty())
      continue;
    for (std::size_t k = 0, first = ring.size(); k < first; ++k)
      for (pcl::index_t j : hoods_[static_cast<std::size_t>(ring[k])]) {
        const auto uj = static_cast<std::size_t>(j);
        if (result_.labels[uj] >= 0 && result_.labels[uj] != own && stamp[uj] != generation) {
          stamp[uj] = generation;
          ring.push_back(j);
        }
      }
    // A wide region's own points decide its type, unless its normals turn: a fillet's middle band
    // can be flat to within the noise of distances and still turn its normals by tens of degrees.
    const bool wide = ring.size() < members.size();
    const double own_angle = wide ? medianAngle(members, fits_[r].refined) : 0.0;
    std::vector<double> held(ring.size());  // each contested point's capped d² to its own
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const double t = grower.tolerance(ring[k]);
      const auto label =
          static_cast<std::size_t>(result_.labels[static_cast<std::size_t>(ring[k])]);
      held[k] = std::min(t * t, std::pow(distance(points_.col(ring[k]), fits_[label].refined), 2));
    }
    // The contested points' capped squared distances with the candidate, and how many it takes.
    const auto contest = [&](const Primitive& candidate, std::size_t& taken) {
      double sum = 0.0;
      taken = 0;
      for (std::size_t k = 0; k < ring.size(); ++k) {
        double d2 = held[k];
        if (grower.accepts(ring[k], candidate)) {
          const double c2 = std::pow(distance(points_.col(ring[k]), candidate), 2);
          if (c2 < d2) {
            d2 = c2;
            ++taken;
          }
        }
        sum += d2;
      }
      return sum;
    };
    const double log_n = std::log(static_cast<double>(members.size() + ring.size()));
    std::size_t taken = 0;
    double best = contest(fits_[r].refined, taken) + parameterCount(fits_[r].type) * sigma2 * log_n;
    const Eigen::Matrix3Xd own_points = points_(Eigen::all, members);
    std::optional<FitResult> choice;
    for (const auto& [type, name] : kPrimitiveTypeNames) {
      if (type == fits_[r].type)
        continue;
      FitResult fit = grower.fit(type, members);
      if (!fit.ok() || isNearlyDegenerate(fit.refined, own_points) ||
          fit.rms_distance > (1.0 + kAdequacyMargin) * fits_[r].rms_distance)
        continue;
      if (wide && !(kNormalTurnRatio * medianAngle(members, fit.refined) < own_angle))
        continue;
      const double c = contest(fit.refined, taken) + parameterCount(type) * sigma2 * log_n;
      if (c < best && taken >= 3 * static_cast<std::size_t>(parameterCount(type))) {
        best = c;
        choice = std::move(fit);
      }
    }
    if (choice) {
      fits_[r] = std::move(*choice);
      ++result_.revised;
    }
  }
}

void SegmentationKernel::recoverFillets() {
  // A fillet of radius r between two planes lies within ε of them except its middle rows, up to
  // r (1 − sin(opening / 2)) off both: at r ≈ 20 σ the planes take it all as they grow (THEORY §6
  // step 6c). For each pair of plane regions that touch (or meet across one free point) at a
  // crease, the cross-section's fillet radius is fitted on the points near the crease, and the
  // fillet is kept when its gain over the sharp crease (in squared σ) beats its parameters' cost
  // by the Bayesian information criterion and its arc holds min_points.
  RegionGrower& grower = *grower_;
  auto planeOf = [&](std::size_t r) -> const Plane* {
    return alive_[r] && regions_[r].size() >= result_.min_points
               ? std::get_if<Plane>(&fits_[r].refined)
               : nullptr;
  };
  std::set<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t r = 0; r < regions_.size(); ++r) {
    if (!planeOf(r))
      continue;
    auto note = [&](int other) {
      if (other >= 0 && static_cast<std::size_t>(other) > r &&
          planeOf(static_cast<std::size_t>(other)))
        pairs.emplace(r, static_cast<std::size_t>(other));
    };
    for (int i : regions_[r])
      for (pcl::index_t j : hoods_[static_cast<std::size_t>(i)]) {
        const int lj = result_.labels[static_cast<std::size_t>(j)];
        if (lj >= 0) {
          note(lj);
          continue;
        }
        for (pcl::index_t k : hoods_[static_cast<std::size_t>(j)])
          note(result_.labels[static_cast<std::size_t>(k)]);
      }
  }
  const double crease_cos = std::cos(result_.max_angle);
  for (const auto& [a, b] : pairs) {
    const Plane* pa = planeOf(a);
    const Plane* pb = planeOf(b);
    if (!pa || !pb || std::abs(pa->normal.dot(pb->normal)) > crease_cos)
      continue;
    const std::optional<CreaseSection> section =
        creaseSection(*pa, *pb, points_(Eigen::all, regions_[a]), points_(Eigen::all, regions_[b]));
    if (!section)
      continue;
    // The largest radius puts the tangent points halfway across the narrower plane; the smallest
    // is twice the tolerance (a fillet within it is an edge).
    auto reach = [&](const std::vector<int>& members, const Eigen::Vector3d& u) {
      double most = 0.0;
      for (int i : members)
        most = std::max(most, u.dot(points_.col(i) - section->origin));
      return most;
    };
    const double half = 0.5 * section->opening;
    const double largest =
        0.5 * std::min(reach(regions_[a], section->ua), reach(regions_[b], section->ub)) *
        std::tan(half);
    const double smallest = 2.0 * std::max(grower.smallestTolerance(regions_[a]),
                                           grower.smallestTolerance(regions_[b]));
    if (!(largest > smallest))
      continue;
    // The band: members and their free neighbours no further from the crease than the largest
    // fillet's tangent points, and a tolerance.
    const double band = largest / std::tan(half);
    std::vector<int> near;
    auto inBand = [&](int i) {
      Eigen::Vector3d q = points_.col(i) - section->origin;
      q -= section->along.dot(q) * section->along;
      return q.norm() <= band + 3.0 * grower.tolerance(i);
    };
    for (std::size_t r : {a, b})
      for (int i : regions_[r])
        if (inBand(i)) {
          near.push_back(i);
          for (pcl::index_t j : hoods_[static_cast<std::size_t>(i)])
            if (result_.labels[static_cast<std::size_t>(j)] < 0 && inBand(j))
              near.push_back(j);
        }
    std::sort(near.begin(), near.end());
    near.erase(std::unique(near.begin(), near.end()), near.end());
    // The radius is chosen on at most kFilletSample of them (evenly strided).
    const std::size_t stride = 1 + near.size() / kFilletSample;
    std::vector<int> sample;
    for (std::size_t k = 0; k < near.size(); k += stride)
      sample.push_back(near[k]);
    Eigen::VectorXd sigma(static_cast<Eigen::Index>(sample.size()));
    for (std::size_t k = 0; k < sample.size(); ++k)
      sigma(static_cast<Eigen::Index>(k)) = grower.tolerance(sample[k]) / kNoiseFactor;
    const FilletChoice choice =
        chooseFilletRadius(*section, points_(Eigen::all, sample), sigma, smallest, largest);
    const double n = static_cast<double>(sample.size());
    if (!(choice.radius > 0.0) ||
        choice.sharp_cost - choice.cost <= kFilletParameters * std::log(n) ||
        choice.on_arc * stride < result_.min_points)
      continue;
    std::vector<int> arc;
    for (int i : near) {
      double d = 0.0;
      if (filletDistance(*section, choice.radius, points_.col(i), &d) == FilletPiece::arc &&
          d <= grower.tolerance(i))
        arc.push_back(i);
    }
    if (arc.size() < result_.min_points)
      continue;
    FitResult fit = grower.fit(PrimitiveType::cylinder, arc);
    const auto* cylinder = std::get_if<Cylinder>(&fit.refined);
    if (!fit.ok() || !cylinder || std::abs(cylinder->axis.dot(section->along)) < crease_cos ||
        cylinder->radius > 2.0 * choice.radius || cylinder->radius < 0.5 * choice.radius)
      continue;
    ++result_.fillets;
    addRegion(arc, std::move(fit), SlippageType::cylinder);
    for (std::size_t r : {a, b}) {
      const auto label = static_cast<std::int32_t>(r);
      auto& members = regions_[r];
      members.erase(std::remove_if(members.begin(), members.end(),
                                   [&](int i) {
                                     return result_.labels[static_cast<std::size_t>(i)] != label;
                                   }),
                    members.end());
      FitResult refit = grower.fit(PrimitiveType::plane, members);
      if (refit.ok())
        fits_[r] = std::move(refit);
    }
  }
}

double SegmentationKernel::normalAngle(int i, const Primitive& primitive) const {
  const double c = std::abs(surfaceNormal(points_.col(i), primitive).dot(normals_.col(i)));
  return std::acos(std::min(1.0, c));
}

void SegmentationKernel::drop(std::size_t region) {
  for (int i : regions_[region])
    result_.labels[static_cast<std::size_t>(i)] = -1;
  regions_[region].clear();
  alive_[region] = 0;
}

void SegmentationKernel::relabelFromRegions() {
  for (auto& region : regions_)
    region.clear();
  for (std::size_t i = 0; i < n_; ++i)
    if (result_.labels[i] >= 0)
      regions_[static_cast<std::size_t>(result_.labels[i])].push_back(static_cast<int>(i));
}

void SegmentationKernel::refineBoundaries() {
  // A point that the neighboring segment's primitive explains better than its own moves there — a
  // plane that took the first rows of a tangent fillet gives them back. Better: nearer (within ε,
  // normal within α); where two primitives are within 2σ̂ of each other at the point (a tangent
  // junction: a fillet point θ from the tangent line is r θ²/2 off the plane), by the cost of
  // `cost` below, which averages the noise over the neighborhood and adds the normal's angle
  // (linear in θ, not quadratic); a point stays unless another is better by kStayCost. Up to
  // kBoundaryPasses passes, each on refits of the regions that changed, while the moves settle
  // (kSettling: on PCL's Kinect scans the rim segments crept into the table a ring per pass).
  // With the carry-back's tie rule, the 1 M-point scenes (seeds 11–13, 21–26) rose from a mean
  // IoU of 0.969 to 0.981; Fit4CAD's Dice went from 0.9258 to 0.9246 (see bench/README.md).
  RegionGrower& grower = *grower_;
  std::vector<char> changed(regions_.size(), 0);
  // The normal noise: the median angle between members' normals and their primitive's (a
  // Rayleigh median is 1.177 σ_θ).
  std::vector<double> angles;
  for (std::size_t r = 0; r < regions_.size(); ++r)
    if (alive_[r])
      for (std::size_t m = 0; m < regions_[r].size(); m += 7)
        angles.push_back(normalAngle(regions_[r][m], fits_[r].refined));
  const double sigma_angle = angles.empty() ? 1.0 : std::max(quantile(angles, 0.5) / 1.177, 1e-3);
  const double sigma_distance =
      std::sqrt(result_.noise * result_.noise + edge_margin_ * edge_margin_);
  // The cost of a primitive at point i: its neighborhood's mean signed distance (at a tangent
  // junction the other primitive's bias r θ²/2 is one-signed and survives the mean while the noise
  // shrinks by √k) in units of the noise of that mean, and the angle of the point's normal.
  const auto cost = [&](std::size_t i, const Primitive& primitive) {
    const Eigen::Vector3d p = points_.col(static_cast<Eigen::Index>(i));
    double sum = signedDistance(p, primitive);
    for (pcl::index_t j : hoods_[i])
      sum += signedDistance(points_.col(j), primitive);
    const double count = static_cast<double>(hoods_[i].size() + 1);
    const double mean = sum / count / (sigma_distance / std::sqrt(count));
    const double angle = normalAngle(static_cast<int>(i), primitive) / sigma_angle;
    return mean * mean + angle * angle;
  };
  std::size_t previous_moves = 0;
  for (int pass = 0; pass < kBoundaryPasses; ++pass) {
    for (std::size_t r = 0; r < regions_.size(); ++r)
      if (alive_[r] && changed[r]) {
        FitResult refit = grower.fit(fits_[r].type, regions_[r]);
        if (refit.ok())
          fits_[r] = std::move(refit);
      }
    std::vector<std::pair<int, std::int32_t>> moves;
    for (std::size_t i = 0; i < n_; ++i) {
      const std::int32_t own = result_.labels[i];
      if (own < 0)
        continue;
      // The candidates: its own primitive and those of its neighbors' segments that accept it.
      std::array<std::int32_t, 8> candidates{own};
      std::array<double, 8> d{};
      std::size_t count = 1;
      for (pcl::index_t j : hoods_[i]) {
        const std::int32_t other = result_.labels[static_cast<std::size_t>(j)];
        if (other < 0 || count == candidates.size() ||
            std::find(candidates.begin(), candidates.begin() + count, other) !=
                candidates.begin() + count ||
            !grower.accepts(static_cast<int>(i), fits_[static_cast<std::size_t>(other)].refined))
          continue;
        candidates[count++] = other;
      }
      if (count == 1)
        continue;
      const Eigen::Vector3d p = points_.col(static_cast<Eigen::Index>(i));
      std::size_t nearest = 0;
      for (std::size_t c = 0; c < count; ++c) {
        d[c] = distance(p, fits_[static_cast<std::size_t>(candidates[c])].refined);
        if (d[c] < d[nearest])
          nearest = c;
      }
      // The nearest, unless another is as near within the noise: then the neighborhood decides,
      // and the point stays unless another is better by kStayCost (a tie of noisy normals would
      // otherwise let a segment creep a ring per pass).
      const double margin = kTieShare * grower.tolerance(static_cast<int>(i));
      std::size_t choice = nearest;
      std::size_t close = 0;
      for (std::size_t c = 0; c < count; ++c)
        close += d[c] <= d[nearest] + margin ? 1 : 0;
      if (close > 1) {
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t c = 0; c < count; ++c)
          if (d[c] <= d[nearest] + margin) {
            const double e = cost(i, fits_[static_cast<std::size_t>(candidates[c])].refined) -
                             (c == 0 ? kStayCost : 0.0);
            if (e < best) {
              best = e;
              choice = c;
            }
          }
      }
      const std::int32_t label = candidates[choice];
      if (label != own)
        moves.emplace_back(static_cast<int>(i), label);
    }
    // A boundary settling moves fewer points each pass; a segment creeping into its neighbor
    // (refitted on what it took, it takes the next ring: noisy depth at a table's rim) does not.
    if (moves.empty() || (pass >= 2 && static_cast<double>(moves.size()) >
                                           kSettling * static_cast<double>(previous_moves)))
      break;
    previous_moves = moves.size();
    for (const auto& [i, label] : moves) {
      changed[static_cast<std::size_t>(result_.labels[static_cast<std::size_t>(i)])] = 1;
      changed[static_cast<std::size_t>(label)] = 1;
      result_.labels[static_cast<std::size_t>(i)] = label;
    }
    relabelFromRegions();
    for (std::size_t r = 0; r < regions_.size(); ++r)
      if (alive_[r] && regions_[r].size() < static_cast<std::size_t>(minimumPoints(fits_[r].type)))
        drop(r);
  }
  shareEdges();
}

void SegmentationKernel::shareEdges() {
  // A point that two adjacent primitives explain equally well — both within its tolerance, their
  // distances within the floor of noise-free data (s/20: no measurement tells them apart) — lies
  // on their edge: it belongs to both, and its label goes to the smaller segment, whose share of
  // it is the larger (the Dice-optimal tie: Fit4CAD labels such points with both faces). With
  // noise the nearest primitive keeps them (a margin of σ̂ cost the 100k scenes 0.013 of IoU).
  const RegionGrower& grower = *grower_;
  std::vector<std::size_t> size(regions_.size());
  for (std::size_t r = 0; r < regions_.size(); ++r)
    size[r] = regions_[r].size();
  std::vector<std::pair<int, std::int32_t>> moves;
  for (std::size_t i = 0; i < n_; ++i) {
    const std::int32_t own = result_.labels[i];
    if (own < 0)
      continue;
    const auto ii = static_cast<int>(i);
    const Eigen::Vector3d p = points_.col(ii);
    const double tolerance = grower.tolerance(ii);
    const double tie = distance(p, fits_[static_cast<std::size_t>(own)].refined) + edge_margin_;
    std::int32_t label = own;
    for (pcl::index_t j : hoods_[i]) {
      const std::int32_t other = result_.labels[static_cast<std::size_t>(j)];
      if (other < 0 || other == label ||
          size[static_cast<std::size_t>(other)] >= size[static_cast<std::size_t>(label)])
        continue;
      const double d = distance(p, fits_[static_cast<std::size_t>(other)].refined);
      if (d <= tolerance && d <= tie)
        label = other;
    }
    if (label != own)
      moves.emplace_back(ii, label);
  }
  for (const auto& [i, label] : moves)
    result_.labels[static_cast<std::size_t>(i)] = label;
  if (!moves.empty())
    relabelFromRegions();
}

void SegmentationKernel::joinCreases() {
  // Points left over at creases (where estimated normals blur) join an adjacent region whose
  // primitive is within their distance tolerance (the normal test is waived): the nearest, or of
  // several as near (within s/20) the smallest (see shareEdges).
  const RegionGrower& grower = *grower_;
  for (int pass = 0, assigned = 1; assigned && pass < 2; ++pass) {
    assigned = 0;
    std::vector<std::pair<int, std::int32_t>> joins;
    for (std::size_t i = 0; i < n_; ++i) {
      if (result_.labels[i] >= 0)
        continue;
      const auto ii = static_cast<int>(i);
      const Eigen::Vector3d p = points_.col(ii);
      const double tolerance = grower.tolerance(ii);
      double nearest = tolerance;
      for (pcl::index_t j : hoods_[i]) {
        const std::int32_t other = result_.labels[static_cast<std::size_t>(j)];
        if (other >= 0)
          nearest = std::min(nearest, distance(p, fits_[static_cast<std::size_t>(other)].refined));
      }
      std::int32_t label = -1;
      for (pcl::index_t j : hoods_[i]) {
        const std::int32_t other = result_.labels[static_cast<std::size_t>(j)];
        if (other < 0 || other == label ||
            (label >= 0 && regions_[static_cast<std::size_t>(other)].size() >=
                               regions_[static_cast<std::size_t>(label)].size()))
          continue;
        const double d = distance(p, fits_[static_cast<std::size_t>(other)].refined);
        if (d <= tolerance && d <= nearest + edge_margin_)
          label = other;
      }
      if (label >= 0)
        joins.emplace_back(static_cast<int>(i), label);
    }
    for (const auto& [i, label] : joins) {
      result_.labels[static_cast<std::size_t>(i)] = label;
      regions_[static_cast<std::size_t>(label)].push_back(i);
      assigned = 1;
    }
  }
}

std::vector<double> SegmentationKernel::regionSpacings() const {
  std::vector<double> spacings(regions_.size(), 0.0);
  for (std::size_t r = 0; r < regions_.size(); ++r)
    if (alive_[r])
      spacings[r] = medianNearestDistance(hoods_, regions_[r]);
  return spacings;
}

bool SegmentationKernel::isScattered(const std::vector<int>& set,
                                     const std::vector<double>& spacings,
                                     std::vector<std::uint32_t>& stamp,
                                     std::uint32_t& generation) const {
  // The densest region around, not its points next to the set: those are often outliers that
  // joined it within tolerance, as sparse as the set.
  double around = spacing_;
  bool found = false;
  for (int i : set)
    for (pcl::index_t j : hoods_[static_cast<std::size_t>(i)]) {
      const auto r = static_cast<std::size_t>(result_.labels[static_cast<std::size_t>(j)]);
      if (result_.labels[static_cast<std::size_t>(j)] >= 0 && r < spacings.size() &&
          spacings[r] > 0.0 && (!found || spacings[r] < around)) {
        around = spacings[r];
        found = true;
      }
    }
  ++generation;
  for (int i : set)
    stamp[static_cast<std::size_t>(i)] = generation;
  return medianNearestWithin(hoods_, set, stamp, generation) > kScattered * around;
}

void SegmentationKernel::recoverSmallFaces() {
  // Free points left after the crease pass are within tolerance of no adjacent primitive. A
  // connected patch of them is a face too small to have seeded (the wall of a hole two rows of
  // points deep, a narrow fillet: every neighborhood there straddles an edge), and its edge rows
  // were taken by the faces around it. The patch is fitted with the simplest adequate type; the
  // edge points it explains as well as their own primitive (a tie within s/20, see shareEdges)
  // join it, and the type is chosen again with them (two rows of a hole lie on a sphere too, four
  // do not). The patch becomes a region when the fit holds most of its own points and three per
  // parameter, and with its edges it reaches min_points. A patch that no one primitive explains
  // (a row of narrow faces, each too small to seed) is tried face by face: from each of its
  // points in turn, the free points of its two rings grown over the patch by their fit.
  RegionGrower& grower = *grower_;
  std::vector<char> seen(n_, 0), used(n_, 0);
  std::vector<std::uint32_t> stamp(n_, 0);
  std::uint32_t generation = 0;
  bool recovered = false;
  Eigen::Matrix3Xd own(3, static_cast<Eigen::Index>(n_));  // normals within a face: see below
  std::vector<char> known(n_, 0);
  const double cos_angle = std::cos(result_.max_angle);
  // Faces recovered here do not vouch for the density of others: outliers would vouch for
  // outliers.
  const std::vector<double> grown_spacing = regionSpacings();
  // The free points among the neighbors of free point i and among those of its labelled
  // neighbors: a wall whose free rows are cut by the edge rows the faces took stays one patch.
  const auto forEachFreeNear = [&](int i, const auto& visit) {
    for (pcl::index_t j : hoods_[static_cast<std::size_t>(i)]) {
      if (result_.labels[static_cast<std::size_t>(j)] < 0) {
        visit(j);
        continue;
      }
      for (pcl::index_t l : hoods_[static_cast<std::size_t>(j)])
        if (result_.labels[static_cast<std::size_t>(l)] < 0)
          visit(l);
    }
  };
  // Tries the free points \a face as one region; true when it becomes one.
  const auto tryFace = [&](const std::vector<int>& face, SlippageType seed_type,
                           bool check_normals) {
    if (face.size() < kSmallestPatch)
      return false;
    ++generation;
    std::vector<int> rim;  // labelled neighbours of the face
    for (int i : face)
      for (pcl::index_t j : hoods_[static_cast<std::size_t>(i)]) {
        const auto uj = static_cast<std::size_t>(j);
        if (result_.labels[uj] >= 0 && stamp[uj] != generation) {
          stamp[uj] = generation;
          rim.push_back(j);
        }
      }
    std::sort(rim.begin(), rim.end());
    // Outliers scattered through the volume are free points too (THEORY §6 step 8b).
    if (isScattered(face, grown_spacing, stamp, generation))
      return false;
    estimateOwnNormals(points_, normals_, hoods_, face, stamp, ++generation, own, known);
    FitResult fit = fitSet(points_, own, face);
    std::vector<int> members, edges;
    for (int round = 0; round < 2 && fit.ok(); ++round) {
      members.clear();
      for (int i : face)
        if (grower.near(i, fit.refined) &&
            (!check_normals || !known[static_cast<std::size_t>(i)] ||
             std::abs(surfaceNormal(points_.col(i), fit.refined).dot(own.col(i))) >= cos_angle))
          members.push_back(i);
      edges.clear();
      for (int j : rim) {
        const double d = distance(points_.col(j), fit.refined);
        const auto own = static_cast<std::size_t>(result_.labels[static_cast<std::size_t>(j)]);
        if (d <= grower.tolerance(j) &&
            d <= distance(points_.col(j), fits_[own].refined) + edge_margin_)
          edges.push_back(j);
      }
      if (round == 1)
        break;
      std::vector<int> all = members;
      all.insert(all.end(), edges.begin(), edges.end());
      estimateOwnNormals(points_, normals_, hoods_, all, stamp, ++generation, own, known);
      FitResult refit = fitSet(points_, own, all);
      if (!refit.ok())
        break;
      fit = std::move(refit);
    }
    if (!fit.ok() ||
        static_cast<double>(members.size()) < kHeld * static_cast<double>(face.size()) ||
        members.size() < 3 * static_cast<std::size_t>(parameterCount(fit.type)) ||
        members.size() + edges.size() < result_.min_points)
      return false;
    members.insert(members.end(), edges.begin(), edges.end());
    addRegion(std::move(members), std::move(fit), seed_type);
    recovered = true;
    return true;
  };
  for (std::size_t s = 0; s < n_; ++s) {
    if (result_.labels[s] >= 0 || seen[s])
      continue;
    std::vector<int> patch{static_cast<int>(s)};
    seen[s] = 1;
    for (std::size_t head = 0; head < patch.size(); ++head)
      forEachFreeNear(patch[head], [&](int j) {
        if (!seen[static_cast<std::size_t>(j)]) {
          seen[static_cast<std::size_t>(j)] = 1;
          patch.push_back(j);
        }
      });
    if (patch.size() < kSmallestPatch || tryFace(patch, local_types_[s], false))
      continue;
    for (int seed : patch) {
      const auto us = static_cast<std::size_t>(seed);
      if (result_.labels[us] >= 0 || used[us])
        continue;
      // The free points of the seed's two rings, grown over the patch by their fit.
      ++generation;
      std::vector<int> face{seed};
      stamp[us] = generation;
      for (std::size_t head = 0; head < face.size() && head < 1 + hoods_[us].size(); ++head)
        forEachFreeNear(face[head], [&](int j) {
          const auto uj = static_cast<std::size_t>(j);
          if (seen[uj] && stamp[uj] != generation) {
            stamp[uj] = generation;
            face.push_back(j);
          }
        });
      // Each point seeds once, and the two rings of a seed that no primitive fits seed no more.
      used[us] = 1;
      if (face.size() < kSmallestPatch)
        continue;
      // Scattered outliers fail before any fit is made (tryFace checks the grown face again);
      // their points may still seed rings of their own.
      if (isScattered(face, grown_spacing, stamp, generation))
        continue;
      const FitResult fit = grower.fitBest(face);
      if (!fit.ok()) {
        for (int i : face)
          used[static_cast<std::size_t>(i)] = 1;
        continue;
      }
      face.erase(std::remove_if(face.begin(), face.end(),
                                [&](int i) { return !grower.near(i, fit.refined); }),
                 face.end());
      ++generation;
      for (int i : face)
        stamp[static_cast<std::size_t>(i)] = generation;
      for (std::size_t head = 0; head < face.size(); ++head)
        forEachFreeNear(face[head], [&](int j) {
          const auto uj = static_cast<std::size_t>(j);
          if (seen[uj] && stamp[uj] != generation && grower.near(j, fit.refined)) {
            stamp[uj] = generation;
            face.push_back(j);
          }
        });
      for (int i : face)
        used[static_cast<std::size_t>(i)] = 1;
      tryFace(face, local_types_[us], true);
    }
  }
  if (recovered)
    relabelFromRegions();
}

std::vector<std::set<std::size_t>> SegmentationKernel::touchingRegions() const {
  std::vector<std::set<std::size_t>> touching(regions_.size());
  for (std::size_t r = 0; r < regions_.size(); ++r) {
    if (!alive_[r])
      continue;
    for (int i : regions_[r])
      for (pcl::index_t j : hoods_[static_cast<std::size_t>(i)]) {
        const int other = result_.labels[static_cast<std::size_t>(j)];
        if (other >= 0 && static_cast<std::size_t>(other) != r)
          touching[r].insert(static_cast<std::size_t>(other));
      }
  }
  return touching;
}

void SegmentationKernel::absorbFragments() {
  // One noisy surface can grow as several regions: where normals are unreliable (a Kinect's near
  // rows, whose depth steps are about its pixel spacing) growth stops, and the points left between
  // seed specks of their own that never touch the large region before creases are joined. A region
  // joins a neighbor kDominates times its size when that neighbor's primitive explains its points
  // as well as it explains its own (RMS distance no larger): the neighbor's model does not change
  // and the small region is no better explained apart. Each pass decides on the regions as they
  // were before it (chains resolve to the largest), so the order of regions does not matter.
  for (int pass = 0; pass < kAbsorbPasses; ++pass) {
    const std::vector<std::set<std::size_t>> touching = touchingRegions();
    std::vector<double> own(regions_.size(), 0.0);
    for (std::size_t r = 0; r < regions_.size(); ++r)
      if (alive_[r])
        own[r] = rmsOf(points_, regions_[r], fits_[r].refined, nullptr);
    std::vector<std::ptrdiff_t> into(regions_.size(), -1);
    bool any = false;
    for (std::size_t r = 0; r < regions_.size(); ++r) {
      double best = std::numeric_limits<double>::infinity();
      for (const std::size_t b : touching[r]) {
        if (regions_[b].size() < kDominates * regions_[r].size())
          continue;
        const double rms = rmsOf(points_, regions_[r], fits_[b].refined, nullptr);
        if (rms <= own[b] && rms < best) {
          best = rms;
          into[r] = static_cast<std::ptrdiff_t>(b);
        }
      }
      any = any || into[r] >= 0;
    }
    if (!any)
      return;
    for (std::size_t r = 0; r < regions_.size(); ++r) {
      if (into[r] < 0)
        continue;
      auto target = static_cast<std::size_t>(into[r]);
      while (into[target] >= 0)
        target = static_cast<std::size_t>(into[target]);
      for (int i : regions_[r])
        result_.labels[static_cast<std::size_t>(i)] = static_cast<std::int32_t>(target);
      regions_[target].insert(regions_[target].end(), regions_[r].begin(), regions_[r].end());
      regions_[r].clear();
      alive_[r] = 0;
      ++result_.absorbed;
    }
  }
}

void SegmentationKernel::dropNonSurfaces() {
  // A surface, not a volume: points spread uniformly through the slab |D| ≤ ε have an RMS
  // distance of ε/√3 ≈ 0.58 ε; a surface with Gaussian noise (ε = 3σ) about 0.33 ε, quantized
  // depth at most 0.29 ε (its error, uniform within ±step/2, fills half the slab), noise-free data
  // far less. A region above kVolumeRatio ε (each distance in units of its point's tolerance) is
  // random points that happen to lie within ε of some primitive (a cloud of noise): dropped.
  const RegionGrower& grower = *grower_;
  const QuantizedAxis& lattice = result_.lattice;
  for (std::size_t r = 0; r < regions_.size(); ++r) {
    if (!alive_[r])
      continue;
    const std::vector<int>& members = regions_[r];
    double sum = 0.0;
    for (int i : members) {
      const double d = distance(points_.col(i), fits_[r].refined) / grower.tolerance(i);
      sum += d * d;
    }
    // With a quantized axis, a region all on one level is a slice of the sensor's lattice: its
    // shape along that axis is not measured.
    bool one_level = lattice.detected();
    for (std::size_t j = 1; one_level && j < members.size(); ++j)
      one_level = points_(lattice.axis, members[j]) == points_(lattice.axis, members[0]);
    if (one_level || std::sqrt(sum / static_cast<double>(members.size())) > kVolumeRatio) {
      drop(r);
      ++result_.volumes;
    }
  }
}

double SegmentationKernel::precisionRms(const std::vector<int>& members,
                                        const Primitive& primitive) const {
  const Eigen::VectorXd w = grower_->precisionWeights(members);
  double sum = 0.0;
  for (std::size_t j = 0; j < members.size(); ++j) {
    const double d = distance(points_.col(members[j]), primitive);
    sum += w(static_cast<Eigen::Index>(j)) * d * d;
  }
  return members.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(members.size()));
}

SegmentationResult SegmentationKernel::finalize() {
  // Largest first, indices ascending; labels renumbered to match.
  const RegionGrower& grower = *grower_;
  std::vector<std::size_t> order;
  for (std::size_t r = 0; r < regions_.size(); ++r)
    if (alive_[r])
      order.push_back(r);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    return regions_[x].size() > regions_[y].size();
  });
  SegmentationResult result = std::move(result_);
  std::fill(result.labels.begin(), result.labels.end(), -1);
  for (std::size_t k = 0; k < order.size(); ++k) {
    Segment s;
    s.indices = std::move(regions_[order[k]]);
    std::sort(s.indices.begin(), s.indices.end());
    // Refit on the final members (crease points joined after the last fit), kept when it is no
    // worse than the region's fit: a face recovered with its own normals (recoverSmallFaces) is
    // refitted here from the cloud's, which straddle its edges. Each member weighs by its
    // precision (RegionGrower::fitByPrecision): on a quantized scan the far rows, whose steps are
    // several times the near ones', no longer tilt a table.
    s.fit = grower.fitByPrecision(fits_[order[k]].type, s.indices);
    if (!s.fit.ok() ||
        precisionRms(s.indices, s.fit.refined) > precisionRms(s.indices, fits_[order[k]].refined))
      s.fit = std::move(fits_[order[k]]);
    s.seed_type = seed_types_[order[k]];
    refineFromSlippage(points_, normals_, grower.precisionWeights(s.indices), s);
    s.rms_distance = rmsOf(points_, s.indices, s.fit.refined, &s.max_distance);
    for (int i : s.indices)
      result.labels[static_cast<std::size_t>(i)] = static_cast<std::int32_t>(k);
    result.segments.push_back(std::move(s));
  }
  regions_.clear();
  fits_.clear();
  seed_types_.clear();
  alive_.clear();
  return result;
}

void SegmentationKernel::run(Phase phase) {
  switch (phase) {
    case Phase::estimate_scale:
      return estimateScale();
    case Phase::grow_slippage_seeds:
      return growSlippageSeeds();
    case Phase::grow_free_seeds:
      return growFreeSeeds();
    case Phase::merge_regions:
      return mergeRegions();
    case Phase::revise_types:
      return reviseTypes();
    case Phase::recover_fillets:
      return recoverFillets();
    case Phase::refine_boundaries:
      return refineBoundaries();
    case Phase::join_creases:
      return joinCreases();
    case Phase::recover_small_faces:
      return recoverSmallFaces();
    case Phase::absorb_fragments:
      return absorbFragments();
    case Phase::merge_settled_regions:
      return mergeSettledRegions();
    case Phase::drop_non_surfaces:
      return dropNonSurfaces();
  }
}

void SegmentationKernel::runPhases(Phase first, Phase last, std::initializer_list<Phase> skip) {
  for (int k = static_cast<int>(first); k <= static_cast<int>(last); ++k) {
    const auto phase = static_cast<Phase>(k);
    if (std::find(skip.begin(), skip.end(), phase) == skip.end())
      run(phase);
  }
}

}  // namespace slipfit
