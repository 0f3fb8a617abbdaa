#include "slipfit/segmentation.h"

#include "slipfit/depth_quantization.h"
#include "slipfit/exceptions.h"
#include "slipfit/model_selection.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <string>
#include <tuple>

namespace slipfit {

void SegmentationParameters::validate() const {
  if (distance && !(*distance > 0.0 && std::isfinite(*distance)))
    throw InvalidParameterError("segmentation: distance must be > 0");
  if (!(max_angle > 0.0 && max_angle <= 1.5707963267948966 + 1e-12))
    throw InvalidParameterError("segmentation: max_angle must be in (0, 90] degrees");
  if (min_points && *min_points < 3)
    throw InvalidParameterError("segmentation: min_points must be at least 3");
  if (!(merge_factor >= 1.0 && merge_factor <= 10.0))
    throw InvalidParameterError("segmentation: merge_factor must be in [1, 10]");
}

namespace {

double median(std::vector<double> v) {
  if (v.empty())
    return 0.0;
  auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

/// The tolerance from the data: the noise from the spread of each neighborhood off its best
/// plane, the spacing the distance to the nearest other point.
struct DataScale {
  double noise = 0.0;    ///< σ̂, from the lower quartile of the neighborhoods' plane residuals
  double spacing = 0.0;  ///< median nearest-neighbor distance
};

double quantile(std::vector<double> v, double q) {
  if (v.empty())
    return 0.0;
  auto at = v.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), at, v.end());
  return *at;
}

/// q-quantile of χ²_ν / ν by the Wilson–Hilferty approximation, for the z-score \a z of q.
double chiSquareQuantileOverDof(double nu, double z) {
  const double c = 2.0 / (9.0 * nu);
  return std::pow(std::max(0.0, 1.0 - c + z * std::sqrt(c)), 3.0);
}

DataScale dataScale(const Eigen::Ref<const Eigen::Matrix3Xd>& points, const Neighborhoods& hoods) {
  std::vector<double> variance, spacing;
  const std::size_t n = hoods.size();
  const std::size_t stride = std::max<std::size_t>(1, n / 20000);  // a sample is enough
  constexpr double kLowerQuartileZ = -0.6744897501960817;
  for (std::size_t i = 0; i < n; i += stride) {
    const NeighborView v = hoods[i];
    if (v.size() < 5)
      continue;
    spacing.push_back(std::sqrt(static_cast<double>(v.sqr_distances[1])));
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (pcl::index_t j : v)
      mean += points.col(j);
    mean /= static_cast<double>(v.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (pcl::index_t j : v) {
      const Eigen::Vector3d d = points.col(j) - mean;
      cov += d * d.transpose();
    }
    cov /= static_cast<double>(v.size());
    // λ₀ is the mean squared residual of the best plane through the k points; on a smooth surface
    // with Gaussian noise σ, k λ₀ ≈ σ² χ²_ν with ν = k − 3 degrees of freedom. Each neighborhood's
    // value is scaled by the lower quartile of χ²_ν / ν, so that the lower quartile over all
    // neighborhoods estimates σ²: robust to the half of them that straddle edges, thin walls or
    // strong curvature (the median was not: a thin sheet put both faces in most neighborhoods).
    const double k = static_cast<double>(v.size());
    const double lambda0 =
        std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov, Eigen::EigenvaluesOnly)
                          .eigenvalues()(0));
    variance.push_back(lambda0 * k / (k - 3.0) /
                       chiSquareQuantileOverDof(k - 3.0, kLowerQuartileZ));
  }
  return {std::sqrt(quantile(std::move(variance), 0.25)), quantile(std::move(spacing), 0.5)};
}

constexpr std::size_t kSubset = 20000;
// Choosing the type fits every type: an evenly strided 2,000 members decide it as well (the
// RMS of each type is estimated to ~2 % from 2,000 residuals, far below the 25 % margin of
// adequacy), and the chosen type is then refitted on up to kSubset.
constexpr std::size_t kTypeSubset = 2000;

// The default tolerance: 3 σ of the estimated noise (a Gaussian keeps 99.7 % of its points) plus
// a twentieth of the spacing, the floor for noise-free data (CAD: σ ≈ 0), where it admits float
// rounding and the sagitta of fits made on part of a region while it grows.
constexpr double kNoiseFactor = 3.0;
constexpr double kSpacingFactor = 0.05;
// Steps of a quantized axis added to a point's tolerance: see segmentBySlippage.
constexpr double kStepFactor = 2.0;
// The default smallest segment: an absolute count (a fraction of N starves the small shapes of a
// large scene); small faces of CAD parts have 20–60 points.
constexpr std::size_t kDefaultMinPoints = 20;
// Between a surface's RMS distance (≈ 0.33 ε) and that of a slab filled at random (0.58 ε).
constexpr double kVolumeRatio = 0.45;

class Grower {
 public:
  /// \a tolerance: per point, the largest distance of a member.
  Grower(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
         const Eigen::Ref<const Eigen::Matrix3Xd>& normals, const Neighborhoods& hoods,
         std::vector<double> tolerance, double max_angle)
      : points_(points),
        normals_(normals),
        hoods_(hoods),
        tolerance_(std::move(tolerance)),
        cos_angle_(std::cos(max_angle)),
        stamp_(static_cast<std::size_t>(points.cols()), 0) {}

  /// Point \a i's distance tolerance.
  double tolerance(int i) const { return tolerance_[static_cast<std::size_t>(i)]; }

  /// Point \a i lies within its tolerance of \a primitive.
  bool near(int i, const Primitive& primitive) const {
    return distance(points_.col(i), primitive) <= tolerance(i);
  }

  bool accepts(int i, const Primitive& primitive) const {
    const Eigen::Vector3d p = points_.col(i);
    if (!(distance(p, primitive) <= tolerance(i)))
      return false;
    return std::abs(surfaceNormal(p, primitive).dot(normals_.col(i))) >= cos_angle_;
  }

  /// Fits \a type to the members; with \a all false, to an evenly strided subset of at most
  /// kSubset of them (statistically plenty while a region grows or merges: the final fit of each
  /// segment uses every member).
  FitResult fit(PrimitiveType type, const std::vector<int>& members, bool all = false) const {
    Eigen::Matrix3Xd p, n;
    gather(members, all, p, n);
    return fitPrimitive(type, p, n, Eigen::VectorXd::Ones(p.cols()));
  }

  /// The simplest adequate type for the members (with \a refine false: closed forms only, a
  /// quick look at a seed's neighborhood).
  FitResult fitBest(const std::vector<int>& members, bool refine = true) const {
    Eigen::Matrix3Xd p, n;
    gather(members, false, p, n, kTypeSubset);
    FitOptions options;
    options.refine = refine;
    return fitAuto(p, n, Eigen::VectorXd::Ones(p.cols()), options);
  }

  /// Median distance of the (strided) members to \a primitive.
  double medianDistance(const std::vector<int>& members, const Primitive& primitive) const {
    const std::size_t stride = std::max<std::size_t>(1, members.size() / kSubset);
    std::vector<double> d;
    for (std::size_t j = 0; j < members.size(); j += stride)
      d.push_back(distance(points_.col(members[j]), primitive));
    return median(std::move(d));
  }

  /// Grows from \a members (kept) over unlabelled points accepted by the fit, refitting each
  /// time the region doubles. Returns the final fit (type fixed).
  FitResult grow(PrimitiveType type, std::vector<int>& members, FitResult fit,
                 const std::vector<std::int32_t>& labels) {
    ++generation_;
    for (int i : members)
      stamp_[static_cast<std::size_t>(i)] = generation_;
    std::size_t fitted_size = members.size();
    for (std::size_t head = 0; head < members.size(); ++head) {
      const NeighborView v = hoods_[static_cast<std::size_t>(members[head])];
      for (pcl::index_t j : v) {
        const auto uj = static_cast<std::size_t>(j);
        if (stamp_[uj] == generation_ || labels[uj] >= 0)
          continue;
        if (!accepts(j, fit.refined))
          continue;
        stamp_[uj] = generation_;
        members.push_back(j);
      }
      if (members.size() >= 2 * fitted_size) {
        FitResult refit = this->fit(type, members);
        if (refit.ok())
          fit = std::move(refit);
        fitted_size = members.size();
      }
    }
    return fit;
  }

  void gather(const std::vector<int>& members, bool all, Eigen::Matrix3Xd& p, Eigen::Matrix3Xd& n,
              std::size_t subset = kSubset) const {
    const std::size_t stride = all ? 1 : std::max<std::size_t>(1, members.size() / subset);
    const auto m = static_cast<Eigen::Index>((members.size() + stride - 1) / stride);
    p.resize(3, m);
    n.resize(3, m);
    for (Eigen::Index j = 0; j < m; ++j) {
      const int i = members[static_cast<std::size_t>(j) * stride];
      p.col(j) = points_.col(i);
      n.col(j) = normals_.col(i);
    }
  }

  /// Keeps the members the fit accepts.
  void prune(std::vector<int>& members, const Primitive& primitive) const {
    members.erase(std::remove_if(members.begin(), members.end(),
                                 [&](int i) { return !accepts(i, primitive); }),
                  members.end());
  }

 private:
  const Eigen::Ref<const Eigen::Matrix3Xd>& points_;
  const Eigen::Ref<const Eigen::Matrix3Xd>& normals_;
  const Neighborhoods& hoods_;
  std::vector<double> tolerance_;
  double cos_angle_;
  std::vector<std::uint32_t> stamp_;
  std::uint32_t generation_ = 0;
};

/// Two planes more than the angle tolerance apart never merge; other pairs are tried.
bool mayMerge(const Primitive& a, const Primitive& b, double max_angle) {
  const auto* pa = std::get_if<Plane>(&a);
  const auto* pb = std::get_if<Plane>(&b);
  return !(pa && pb) || std::abs(pa->normal.dot(pb->normal)) >= std::cos(max_angle);
}

/// The segment's own slippage verdict, and its primitive as a second start of the refinement.
void refineFromSlippage(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                        const Eigen::Ref<const Eigen::Matrix3Xd>& normals, Segment& s) {
  const auto m = static_cast<Eigen::Index>(s.indices.size());
  Eigen::Matrix3Xd p(3, m), n(3, m);
  for (Eigen::Index j = 0; j < m; ++j) {
    p.col(j) = points.col(s.indices[static_cast<std::size_t>(j)]);
    n.col(j) = normals.col(s.indices[static_cast<std::size_t>(j)]);
  }
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(m);
  s.slippage = analyzeSlippage(p, n, w);
  if (!s.slippage->primitive || typeOf(*s.slippage->primitive) != s.fit.type)
    return;
  const Primitive start = refinePrimitive(*s.slippage->primitive, p, w, 100);
  const double loss = weightedLoss(p, w, start);
  if (loss < weightedLoss(p, w, s.fit.refined)) {
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

}  // namespace

SegmentationResult segmentBySlippage(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                     const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                                     const Neighborhoods& hoods,
                                     const std::vector<SlippageType>& local_types,
                                     const SegmentationParameters& parameters) {
  parameters.validate();
  const auto n = static_cast<std::size_t>(points.cols());
  if (n == 0)
    throw DegenerateInputError("segmentation: the cloud is empty");
  if (static_cast<std::size_t>(normals.cols()) != n || hoods.size() != n || local_types.size() != n)
    throw DegenerateInputError(
        "segmentation: points, normals, neighborhoods and local types differ in number");
  if (!normals.allFinite())
    throw DegenerateInputError("segmentation: some normals are missing (NaN)");

  SegmentationResult result;
  // A coordinate recorded on levels (Kinect-like depth) puts a point up to half a step off its
  // surface along that axis, and a disparity sensor's noise grows with depth as its step does
  // (about half a step): each point's tolerance adds kStepFactor local steps to the tolerance
  // from the noise and spacing.
  result.lattice = detectQuantizedAxis(points);
  result.step_factor = result.lattice.detected() ? kStepFactor : 0.0;
  const DataScale scale = dataScale(points, hoods);
  result.noise = scale.noise;
  result.distance =
      parameters.distance.value_or(kNoiseFactor * scale.noise + kSpacingFactor * scale.spacing);
  if (!(result.distance > 0.0))
    throw DegenerateInputError(
        "segmentation: cannot derive a distance tolerance (all points coincide); set distance");
  result.max_angle = parameters.max_angle;
  std::vector<double> tolerance(n);
  for (std::size_t i = 0; i < n; ++i)
    tolerance[i] = result.tolerance(points.col(static_cast<Eigen::Index>(i)));
  result.min_points = parameters.min_points.value_or(kDefaultMinPoints);
  result.labels.assign(n, -1);

  // Seeds: points whose neighbors agree with their own primitive type, most agreement first
  // (ties by index: deterministic).
  std::vector<std::pair<int, int>> seeds;  // (−agreement, index)
  for (std::size_t i = 0; i < n; ++i) {
    if (!primitiveTypeOf(local_types[i]))
      continue;
    int agree = 0;
    for (pcl::index_t j : hoods[i])
      agree += local_types[static_cast<std::size_t>(j)] == local_types[i] ? 1 : 0;
    if (2 * agree > static_cast<int>(hoods[i].size()))
      seeds.emplace_back(-agree, static_cast<int>(i));
  }
  std::sort(seeds.begin(), seeds.end());

  Grower grower(points, normals, hoods, std::move(tolerance), result.max_angle);
  std::vector<char> tried(n, 0);
  std::vector<std::vector<int>> regions;
  std::vector<FitResult> fits;
  std::vector<SlippageType> seed_types;
  // Grows one region from \a members (a seed's neighborhood) with \a type; keeps it when it
  // reaches min_points. \a seed_type is reported with the segment. With \a type_chosen (the
  // type is already the simplest adequate one of the seed's neighborhood) a region that grows
  // to fewer than min_points is dropped at once, without trying the other types.
  auto growRegion = [&](PrimitiveType type, std::vector<int> members, SlippageType seed_type,
                        bool type_chosen) {
    if (static_cast<int>(members.size()) < minimumPoints(type) + 2)
      return;
    FitResult fit = grower.fit(type, members);
    if (!fit.ok())
      return;
    grower.prune(members, fit.refined);
    if (members.empty())
      return;
    ++result.regions_grown;
    fit = grower.grow(type, members, std::move(fit), result.labels);
    if (type_chosen && members.size() < result.min_points) {
      for (int i : members)
        tried[static_cast<std::size_t>(i)] = 1;
      return;
    }
    // The seed's local type can be wrong (a cone patch reads as a cylinder): refit the grown
    // region with the best type and, if it changes, grow again from the region with that type.
    // The local evidence stands unless another type fits clearly better, by the median distance
    // (a BIC margin, or the RMS, lets a wide sphere absorb the crease points of a plane).
    const double current = grower.medianDistance(members, fit.refined);
    FitResult best;
    if (current > result.noise)  // a Gaussian's median |d| is 0.67 σ: this model explains the data
      best = grower.fitBest(members);
    if (current > result.noise && best.ok() && best.type != type &&
        grower.medianDistance(members, best.refined) < 0.75 * current) {
      grower.prune(members, best.refined);
      if (!members.empty())
        fit = grower.grow(best.type, members, std::move(best), result.labels);
    }
    FitResult final_fit = grower.fit(fit.type, members);
    if (final_fit.ok())
      fit = std::move(final_fit);
    grower.prune(members, fit.refined);
    for (int i : members)
      tried[static_cast<std::size_t>(i)] = 1;
    if (members.size() < result.min_points)
      return;
    const auto label = static_cast<std::int32_t>(regions.size());
    for (int i : members)
      result.labels[static_cast<std::size_t>(i)] = label;
    regions.push_back(std::move(members));
    fits.push_back(std::move(fit));
    seed_types.push_back(seed_type);
  };

  // Round 1: seeds whose neighbors agree on the local slippage type, grown with that type.
  for (const auto& [neg_agree, seed] : seeds) {
    const auto us = static_cast<std::size_t>(seed);
    if (result.labels[us] >= 0 || tried[us])
      continue;
    std::vector<int> members;
    for (pcl::index_t j : hoods[us])
      if (result.labels[static_cast<std::size_t>(j)] < 0 &&
          local_types[static_cast<std::size_t>(j)] == local_types[us])
        members.push_back(j);
    tried[us] = 1;
    growRegion(*primitiveTypeOf(local_types[us]), std::move(members), local_types[us], false);
  }

  // Round 2: what is left — small faces whose neighborhoods straddle an edge, so that no point
  // has an agreeing local type — is seeded from every unlabelled point in index order, with the
  // simplest adequate type of its unlabelled neighbors.
  std::fill(tried.begin(), tried.end(), 0);
  for (std::size_t us = 0; us < n; ++us) {
    if (result.labels[us] >= 0 || tried[us])
      continue;
    tried[us] = 1;
    // The seed's free neighbors and theirs (the 2-ring): a seed must hold several times the
    // parameters of the most complex type, or a torus fits any dozen outliers.
    std::vector<int> members;
    for (pcl::index_t j : hoods[us])
      if (result.labels[static_cast<std::size_t>(j)] < 0)
        members.push_back(j);
    if (4 * members.size() < 3 * hoods[us].size())
      continue;  // a point at the crease of a grown segment, not a face of its own
    // A quick look with the closed forms first (outliers fail it by far), then the refined fits.
    const double seed_tolerance = grower.tolerance(static_cast<int>(us));
    const FitResult quick = grower.fitBest(members, false);
    const FitResult start = quick.ok() && quick.rms_distance > seed_tolerance &&
                                    quick.rms_distance <= 3.0 * seed_tolerance
                                ? grower.fitBest(members)
                                : quick;
    // The fit must also hold three points per parameter among the free 2-ring (the seed's free
    // neighbors and theirs): a torus fits any dozen outliers, but not the points around them.
    bool holds = start.ok() && start.rms_distance <= seed_tolerance;
    if (holds) {
      std::vector<int> ring2;
      for (int m : members)
        for (pcl::index_t j : hoods[static_cast<std::size_t>(m)])
          if (result.labels[static_cast<std::size_t>(j)] < 0)
            ring2.push_back(j);
      std::sort(ring2.begin(), ring2.end());
      ring2.erase(std::unique(ring2.begin(), ring2.end()), ring2.end());
      std::size_t held = 0;
      for (int j : ring2)
        held += grower.accepts(j, start.refined) ? 1 : 0;
      holds = held >= 3 * static_cast<std::size_t>(parameterCount(start.type));
    }
    if (!holds) {
      // No surface here (outliers, or an edge): none of these points seeds again.
      for (int j : members)
        tried[static_cast<std::size_t>(j)] = 1;
      continue;
    }
    growRegion(start.type, std::move(members), local_types[us], true);
  }

  // Merge adjacent regions while the best fit of their union (any type: bands of a cone grown
  // as cylinders merge into the cone) is about as good as the parts.
  std::vector<char> alive(regions.size(), 1);
  std::vector<int> version(regions.size(), 0);
  std::set<std::tuple<std::size_t, std::size_t, int, int>> failed;
  for (bool merged = true; merged;) {
    merged = false;
    std::map<std::pair<int, int>, std::size_t> adjacent;  // ordered: deterministic
    for (std::size_t r = 0; r < regions.size(); ++r) {
      if (!alive[r])
        continue;
      for (int i : regions[r])
        for (pcl::index_t j : hoods[static_cast<std::size_t>(i)]) {
          const int other = result.labels[static_cast<std::size_t>(j)];
          if (other > static_cast<int>(r))
            ++adjacent[{static_cast<int>(r), other}];
        }
    }
    for (const auto& [pair, edges] : adjacent) {
      const auto a = static_cast<std::size_t>(pair.first),
                 b = static_cast<std::size_t>(pair.second);
      if (!alive[a] || !alive[b] || !mayMerge(fits[a].refined, fits[b].refined, result.max_angle))
        continue;
      const auto key = std::make_tuple(a, b, version[a], version[b]);
      if (failed.count(key))
        continue;  // tried before, neither has changed since
      // A region four times the other's size dominates the union's fit: its primitive must then
      // hold most of the other's points already.
      const std::size_t big = regions[a].size() >= regions[b].size() ? a : b;
      const std::size_t small = big == a ? b : a;
      if (regions[big].size() >= 4 * regions[small].size()) {
        std::size_t held = 0;
        for (int i : regions[small])
          held += grower.near(i, fits[big].refined) ? 1 : 0;
        if (2 * held < regions[small].size()) {
          failed.insert(key);
          continue;
        }
      }
      std::vector<int> both = regions[a];
      both.insert(both.end(), regions[b].begin(), regions[b].end());
      FitResult fit = grower.fitBest(both);
      const double limit =
          parameters.merge_factor * std::max(fits[a].rms_distance, fits[b].rms_distance);
      if (!fit.ok() || !(fit.rms_distance <= limit)) {
        failed.insert(key);
        continue;
      }
      ++version[a];
      for (int i : regions[b])
        result.labels[static_cast<std::size_t>(i)] = static_cast<std::int32_t>(a);
      regions[a] = std::move(both);
      regions[b].clear();
      fits[a] = std::move(fit);
      alive[b] = 0;
      ++result.merges;
      merged = true;
    }
  }

  // Boundaries: a point that the neighboring segment's primitive explains better than its own
  // (nearer, within ε, normal within α) moves there — a plane that took the first rows of a
  // tangent fillet gives them back. Two passes; the second on refits of the regions that changed
  // (the others' fits are those of their current members).
  std::vector<char> changed(regions.size(), 0);
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t r = 0; r < regions.size(); ++r)
      if (alive[r] && changed[r]) {
        FitResult refit = grower.fit(fits[r].type, regions[r]);
        if (refit.ok())
          fits[r] = std::move(refit);
      }
    std::vector<std::pair<int, std::int32_t>> moves;
    for (std::size_t i = 0; i < n; ++i) {
      const std::int32_t own = result.labels[i];
      if (own < 0)
        continue;
      const Eigen::Vector3d p = points.col(static_cast<Eigen::Index>(i));
      double best = distance(p, fits[static_cast<std::size_t>(own)].refined);
      std::int32_t label = own;
      for (pcl::index_t j : hoods[i]) {
        const std::int32_t other = result.labels[static_cast<std::size_t>(j)];
        if (other < 0 || other == own || other == label)
          continue;
        const Primitive& candidate = fits[static_cast<std::size_t>(other)].refined;
        const double d = distance(p, candidate);
        if (d < best && grower.accepts(static_cast<int>(i), candidate)) {
          best = d;
          label = other;
        }
      }
      if (label != own)
        moves.emplace_back(static_cast<int>(i), label);
    }
    if (moves.empty())
      break;
    for (const auto& [i, label] : moves) {
      changed[static_cast<std::size_t>(result.labels[static_cast<std::size_t>(i)])] = 1;
      changed[static_cast<std::size_t>(label)] = 1;
      result.labels[static_cast<std::size_t>(i)] = label;
    }
    for (auto& region : regions)
      region.clear();
    for (std::size_t i = 0; i < n; ++i)
      if (result.labels[i] >= 0)
        regions[static_cast<std::size_t>(result.labels[i])].push_back(static_cast<int>(i));
    for (std::size_t r = 0; r < regions.size(); ++r)
      if (alive[r] && regions[r].size() < static_cast<std::size_t>(minimumPoints(fits[r].type))) {
        for (int i : regions[r])
          result.labels[static_cast<std::size_t>(i)] = -1;
        regions[r].clear();
        alive[r] = 0;
      }
  }

  // Points left over at creases (where estimated normals blur) join the adjacent region whose
  // primitive is nearest, when within the distance tolerance; the normal test is waived.
  for (int pass = 0, assigned = 1; assigned && pass < 2; ++pass) {
    assigned = 0;
    std::vector<std::pair<int, std::int32_t>> joins;
    for (std::size_t i = 0; i < n; ++i) {
      if (result.labels[i] >= 0)
        continue;
      double best = grower.tolerance(static_cast<int>(i));
      std::int32_t label = -1;
      for (pcl::index_t j : hoods[i]) {
        const std::int32_t other = result.labels[static_cast<std::size_t>(j)];
        if (other < 0 || other == label)
          continue;
        const double d = distance(points.col(static_cast<Eigen::Index>(i)),
                                  fits[static_cast<std::size_t>(other)].refined);
        if (d <= best) {
          best = d;
          label = other;
        }
      }
      if (label >= 0)
        joins.emplace_back(static_cast<int>(i), label);
    }
    for (const auto& [i, label] : joins) {
      result.labels[static_cast<std::size_t>(i)] = label;
      regions[static_cast<std::size_t>(label)].push_back(i);
      assigned = 1;
    }
  }

  // A surface, not a volume: points spread uniformly through the slab |D| ≤ ε have an RMS
  // distance of ε/√3 ≈ 0.58 ε; a surface with Gaussian noise (ε = 3σ) about 0.33 ε, quantized
  // depth at most 0.29 ε (its error, uniform within ±step/2, fills half the slab), noise-free data
  // far less. A region above kVolumeRatio ε (each distance in units of its point's tolerance) is
  // random points that happen to lie within ε of some primitive (a cloud of noise): dropped.
  for (std::size_t r = 0; r < regions.size(); ++r) {
    if (!alive[r])
      continue;
    double sum = 0.0;
    for (int i : regions[r]) {
      const double d = distance(points.col(i), fits[r].refined) / grower.tolerance(i);
      sum += d * d;
    }
    // With a quantized axis, a region all on one level is a slice of the sensor's lattice: its
    // shape along that axis is not measured.
    bool one_level = result.lattice.detected();
    for (std::size_t j = 1; one_level && j < regions[r].size(); ++j)
      one_level = points(result.lattice.axis, regions[r][j]) == points(result.lattice.axis, regions[r][0]);
    if (one_level || std::sqrt(sum / static_cast<double>(regions[r].size())) > kVolumeRatio) {
      for (int i : regions[r])
        result.labels[static_cast<std::size_t>(i)] = -1;
      regions[r].clear();
      alive[r] = 0;
      ++result.volumes;
    }
  }

  // Largest first, indices ascending; labels renumbered to match.
  std::vector<std::size_t> order;
  for (std::size_t r = 0; r < regions.size(); ++r)
    if (alive[r])
      order.push_back(r);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    return regions[x].size() > regions[y].size();
  });
  std::fill(result.labels.begin(), result.labels.end(), -1);
  for (std::size_t k = 0; k < order.size(); ++k) {
    Segment s;
    s.indices = std::move(regions[order[k]]);
    std::sort(s.indices.begin(), s.indices.end());
    // Refit on the final members (crease points joined after the last fit).
    s.fit = grower.fit(fits[order[k]].type, s.indices, true);
    if (!s.fit.ok())
      s.fit = std::move(fits[order[k]]);
    s.seed_type = seed_types[order[k]];
    refineFromSlippage(points, normals, s);
    s.rms_distance = rmsOf(points, s.indices, s.fit.refined, &s.max_distance);
    for (int i : s.indices)
      result.labels[static_cast<std::size_t>(i)] = static_cast<std::int32_t>(k);
    result.segments.push_back(std::move(s));
  }
  return result;
}

}  // namespace slipfit
