// Phases 4, 10, 11 and 13 (merge_regions, absorb_fragments, merge_settled_regions,
// join_occluded_pieces): regions joined when one primitive explains them together.
#include "phases.h"

#include "slipfit/fitting/model_selection.h"
#include "slipfit/segmentation/segmentation_tuning.h"

#include <omp.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <tuple>

namespace slipfit::phases {

namespace {

using T = SegmentationTuning;

/// Two planes more than the angle tolerance apart: their union is no plane, and merging them is a
/// claim that they are facets of one curved surface.
bool isCrease(const Primitive& a, const Primitive& b, double max_angle) {
  const auto* pa = std::get_if<Plane>(&a);
  const auto* pb = std::get_if<Plane>(&b);
  return pa && pb && std::abs(pa->normal.dot(pb->normal)) < std::cos(max_angle);
}

/// One primitive of the larger region's type (\a joint) is the better model of regions a and b
/// together than each region's own, by the Bayesian information criterion.
bool unionIsSimpler(const SegmentationState& s, std::size_t a, std::size_t b,
                    const FitResult& joint) {
  const std::size_t larger = s.regions[a].size() >= s.regions[b].size() ? a : b;
  const std::size_t smaller = larger == a ? b : a;
  if (joint.type != s.fits[larger].type)
    return false;
  // Each region at its own primitive against both at the joint one (BIC, jointModelIsBetter).
  // Below the floor of noise-free data (s.edge_margin per point) distances do not count.
  const auto squares = [&](const std::vector<int>& members, const Primitive& primitive) {
    const double rms = s.rms(members, primitive, nullptr);
    return static_cast<double>(members.size()) * (rms * rms + s.edge_margin * s.edge_margin);
  };
  std::vector<int> both = s.regions[a];
  both.insert(both.end(), s.regions[b].begin(), s.regions[b].end());
  const double separate =
      squares(s.regions[a], s.fits[a].refined) + squares(s.regions[b], s.fits[b].refined);
  return jointModelIsBetter(squares(both, joint.refined), separate, both.size(),
                            parameterCount(s.fits[smaller].type));
}

/// Whether \a fit explains regions a and b together as well as their noise allows: its RMS
/// distance within fitBest's margin of adequacy (kAdequacyMargin) of the regions' noise level.
/// Each region's noise is the mean σᵢ² of its points (SegmentationState::noise) or its own mean
/// squared distance to its primitive where that is lower: a region its model explains better
/// than σ̂ says is evidence that σ̂ is not its noise (a sparse CAD part reads its curvature as
/// σ̂). The data then cannot tell the two regions apart, and the simpler model — one primitive —
/// holds: strips of a narrow cylinder grown as planes and cylinders, or the halves of a sphere,
/// that the crease rule and BIC keep apart on a depth camera's data, whose rounding to levels is
/// correlated along the surface and not the independent noise BIC assumes. Not when one region
/// is T::dominates times the other: so few points move the union's RMS too little to tell, and
/// the rules below judge such unions (on a fillet at σ = r/20 the fillet's fragments went to the
/// planes).
bool explainsWithinNoise(const SegmentationState& s, std::size_t a, std::size_t b,
                         const FitResult& fit) {
  if (s.noise.empty())
    return false;
  const std::size_t na = s.regions[a].size(), nb = s.regions[b].size();
  if (na >= T::dominates * nb || nb >= T::dominates * na)
    return false;
  const auto level = [&](std::size_t r) {
    double sum = 0.0;
    for (int i : s.regions[r])
      sum += s.noise[static_cast<std::size_t>(i)] * s.noise[static_cast<std::size_t>(i)];
    const double own = s.fits[r].rms_distance;
    return std::min(sum, static_cast<double>(s.regions[r].size()) * own * own);
  };
  const double count = static_cast<double>(na + nb);
  const double noise = std::sqrt((level(a) + level(b)) / count);
  return fit.rms_distance <= (1.0 + kAdequacyMargin) * noise;
}

/// The RMS distance of \a members to \a primitive in units of their noise: over the RMS of their
/// σᵢ (each with the floor of noise-free data, s.edge_margin). Over at most \a most of them, evenly
/// spaced: a table of 10⁵ points judged against each of its fragments reads the same ratio from
/// T::ratio_sample of them (relative error about 1/√(2 × 2048) ≈ 1.6 %).
double noiseRatio(const SegmentationState& s, const std::vector<int>& members,
                  const Primitive& primitive,
                  std::size_t most = std::numeric_limits<std::size_t>::max()) {
  double distances = 0.0, noise = 0.0;
  const std::size_t stride = std::max<std::size_t>(1, members.size() / most);
  for (std::size_t k = 0; k < members.size(); k += stride) {
    const int i = members[k];
    const double d = distance(s.points.col(i), primitive);
    const double sigma = s.noise[static_cast<std::size_t>(i)];
    distances += d * d;
    noise += sigma * sigma + s.edge_margin * s.edge_margin;
  }
  return noise > 0.0 ? std::sqrt(distances / noise) : 0.0;
}

/// Whether \a primitive explains each of regions a and b within T::union_noise_ratio times their
/// noise, or times the worse of the two regions' own RMS in units of their noise where that is
/// above 1 (a region its model does not fit within the estimated noise sets the scale the union is
/// judged on). Always, without a noise model (a distance given).
bool keepsWithinNoise(const SegmentationState& s, std::size_t a, std::size_t b,
                      const Primitive& primitive) {
  if (s.noise.empty())
    return true;
  const double own = std::max({1.0, noiseRatio(s, s.regions[a], s.fits[a].refined),
                               noiseRatio(s, s.regions[b], s.fits[b].refined)});
  return noiseRatio(s, s.regions[a], primitive) <= T::union_noise_ratio * own &&
         noiseRatio(s, s.regions[b], primitive) <= T::union_noise_ratio * own;
}

/// Whether \a primitive, the union's, explains the smaller region \a small worse than
/// T::union_noise_ratio times its noise, or times the RMS in units of their noise at which each
/// region's own primitive explains it, where that is worse — when the noise model holds for the
/// larger region \a big (its own ratio within T::union_noise_ratio). A ball or a ring on a far
/// table lies within the table's tolerance (ε plus two depth steps: 4 cm at 2.4 m) and hardly
/// moves the table's RMS, swollen by its far rows' noise; in units of their σᵢ it stands out. A
/// table whose deviations the noise model does not describe (a Kinect's bends by 5 σ̂ over its far
/// rows, PCL's milk-carton scan) is not judged so: its fragments are as far off the plane as it is.
bool standsOut(const SegmentationState& s, std::size_t big, std::size_t small,
               const Primitive& primitive) {
  if (s.noise.empty())
    return false;
  const double big_own = noiseRatio(s, s.regions[big], s.fits[big].refined, T::ratio_sample);
  if (big_own > T::union_noise_ratio)
    return false;
  const double own =
      std::max({1.0, big_own, noiseRatio(s, s.regions[small], s.fits[small].refined)});
  return noiseRatio(s, s.regions[small], primitive) > T::union_noise_ratio * own;
}

/// Whether the merge accepts \a fit as the primitive of regions a and b together: the smaller of a
/// dominated pair does not stand out of its noise under it (standsOut), and its RMS distance is at
/// most merge_factor × the larger of the two regions' (two planes at a crease: below both), or,
/// \a settled, unionIsSimpler; or within their noise (explainsWithinNoise).
bool acceptsUnion(const SegmentationState& s, std::size_t a, std::size_t b, const FitResult& fit,
                  bool settled) {
  if (!fit.ok())
    return false;
  const std::size_t na = s.regions[a].size(), nb = s.regions[b].size();
  if ((na >= T::dominates * nb && standsOut(s, a, b, fit.refined)) ||
      (nb >= T::dominates * na && standsOut(s, b, a, fit.refined)))
    return false;
  if (explainsWithinNoise(s, a, b, fit))
    return true;
  if (settled)
    return unionIsSimpler(s, a, b, fit);
  // Planes meeting at a crease merge only when one curved primitive explains their union
  // better than either plane explains its own points: the facets of a wide fillet whose
  // sagitta over each is within ε (on the 1 M-point scenes, seed 24: 0.940 → 0.949); two
  // faces of a box never do. Other pairs merge while the union's fit is about as good.
  const bool crease = isCrease(s.fits[a].refined, s.fits[b].refined, s.result.max_angle);
  const double limit =
      crease ? std::min(s.fits[a].rms_distance, s.fits[b].rms_distance)
             : s.parameters.merge_factor * std::max(s.fits[a].rms_distance, s.fits[b].rms_distance);
  return fit.rms_distance <= limit;
}

/// A fit of two regions together (of the type fitBest chooses for the union) and whether the
/// merge accepts it (acceptsUnion).
struct UnionTrial {
  FitResult fit;
  bool accepted = false;
};

/// The fit of regions a and b together, judged, or nullopt when the larger (T::dominates × the
/// other) does not hold half of the smaller's points. \a chosen: per region, whether its type is
/// the one fitBest chose for its members. Reads only.
std::optional<UnionTrial> tryMerge(const SegmentationState& s, std::size_t a, std::size_t b,
                                   bool settled, const std::vector<char>& chosen) {
  // A region four times the other's size dominates the union's fit: its primitive must then
  // hold most of the other's points already.
  const RegionGrower& grower = *s.grower;
  const std::size_t big = s.regions[a].size() >= s.regions[b].size() ? a : b;
  const std::size_t small = big == a ? b : a;
  const bool dominated = s.regions[big].size() >= T::dominates * s.regions[small].size();
  if (dominated) {
    std::size_t held = 0;
    for (int i : s.regions[small])
      held += grower.near(i, s.fits[big].refined) ? 1 : 0;
    if (2 * held < s.regions[small].size())
      return std::nullopt;
  }
  std::vector<int> both = s.regions[a];
  both.insert(both.end(), s.regions[b].begin(), s.regions[b].end());
  // A dominated union is most often the larger region's surface with a little more of it (a
  // table taking fragments of its own noise one by one). When fitBest chose the larger's type
  // for its members, and the larger's primitive, refined on the union, explains the union as
  // well as it explained the larger alone (within fitBest's margin of adequacy), the smaller
  // brings no evidence for another type: the union keeps the larger's type without fitting every
  // type again, and converges in a few steps from the larger's primitive. A type that growth
  // kept from a seed is not one fitBest chose: a narrow band of a cylinder grown as a sphere of
  // RMS 0.0037 took cone fragments as a sphere (Fit4CAD PC51, Dice 0.961 → 0.953) where every
  // type tried on the union gives the cylinder.
  // Nor for a simpler type than the larger's: a cone region took fragments of its cylinder as a
  // cone (simulated tabletop seed 2) where every type tried on the union gives the cylinder, the
  // simpler type adequate on the union though not on the larger alone.
  if (dominated && chosen[big]) {
    FitResult near = grower.fitNear(s.fits[big].refined, both);
    if (near.ok() && near.rms_distance <= (1.0 + kAdequacyMargin) * s.fits[big].rms_distance &&
        acceptsUnion(s, a, b, near, settled) &&
        !grower.simplerTypeIsAdequate(near.type, near.rms_distance, both))
      return UnionTrial{std::move(near), true};
  }
  FitResult best = grower.fitBest(both);
  const bool accepted = acceptsUnion(s, a, b, best, settled);
  return UnionTrial{std::move(best), accepted};
}

/// Sets \a chosen for each region that dominates at least two of its neighbors (\a touching) and
/// whose type fitBest chooses for its members: one fit of every type for such a region (a table
/// among the fragments of its noise) in place of one for each union it is tried in.
void confirmTypes(const SegmentationState& s, const std::vector<std::set<std::size_t>>& touching,
                  std::vector<char>& chosen) {
  std::vector<std::size_t> hubs;
  for (std::size_t r = 0; r < touching.size(); ++r) {
    if (!s.alive[r])
      continue;
    std::size_t dominated = 0;
    for (const std::size_t b : touching[r])
      dominated += s.regions[r].size() >= T::dominates * s.regions[b].size() ? 1 : 0;
    if (dominated >= 2)
      hubs.push_back(r);
  }
  const int workers = s.workers();
#pragma omp parallel for schedule(dynamic, 1) num_threads(workers)
  for (std::size_t k = 0; k < hubs.size(); ++k) {
    const FitResult best = s.grower->fitBest(s.regions[hubs[k]]);
    chosen[hubs[k]] = best.ok() && best.type == s.fits[hubs[k]].type ? 1 : 0;
  }
}

/// Merges adjacent regions, round after round: while the union's best fit has an RMS distance
/// at most merge_factor × the larger of the two regions' (two planes at a crease: below both),
/// or, \a settled, while unionIsSimpler.
void mergeAdjacent(SegmentationState& s, bool settled) {
  std::vector<int> version(s.regions.size(), 0);
  std::set<std::tuple<std::size_t, std::size_t, int, int>> failed;
  // Whether each region's type is fitBest's choice for its members: a grown region's type is its
  // seed's, a merged one's is known.
  std::vector<char> chosen(s.regions.size(), 0);
  for (bool merged = true, first = true; merged; first = false) {
    merged = false;
    // Ordered pairs (a < b, a's points having b's among their neighbors): deterministic.
    std::vector<std::pair<std::size_t, std::size_t>> adjacent;
    const std::vector<std::set<std::size_t>> touching = s.touchingRegions();
    if (first)
      confirmTypes(s, touching, chosen);
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
    std::vector<std::optional<UnionTrial>> tried(pairs.size());
    const int workers = s.workers();
#pragma omp parallel for schedule(dynamic, 1) num_threads(workers)
    for (std::size_t k = 0; k < pairs.size(); ++k)
      tried[k] = tryMerge(s, pairs[k].first, pairs[k].second, settled, chosen);
    const std::vector<int> round_version = version;
    std::size_t next = 0;
    for (const auto& [a, b] : adjacent) {
      if (!s.alive[a] || !s.alive[b])
        continue;
      const auto key = std::make_tuple(a, b, version[a], version[b]);
      if (failed.count(key))
        continue;  // tried before, neither has changed since
      while (next < pairs.size() && pairs[next] < std::make_pair(a, b))
        ++next;
      std::optional<UnionTrial> trial =
          next < pairs.size() && pairs[next] == std::make_pair(a, b) &&
                  version[a] == round_version[a] && version[b] == round_version[b]
              ? std::move(tried[next])
              : tryMerge(s, a, b, settled, chosen);
      if (!trial || !trial->accepted) {
        failed.insert(key);
        continue;
      }
      ++version[a];
      s.moveInto(b, a);
      s.fits[a] = std::move(trial->fit);
      chosen[a] = 1;
      ++s.result.merges;
      merged = true;
    }
  }
}

/// Up to T::piece_sample of \a members, evenly spaced.
std::vector<int> sampleOf(const std::vector<int>& members) {
  std::vector<int> sample;
  const std::size_t stride = std::max<std::size_t>(1, members.size() / T::piece_sample);
  for (std::size_t k = 0; k < members.size(); k += stride)
    sample.push_back(members[k]);
  return sample;
}

/// The largest distance between two of \a sample's points: its extent.
double extent(const SegmentationState& s, const std::vector<int>& sample) {
  double widest = 0.0;
  for (std::size_t j = 0; j < sample.size(); ++j)
    for (std::size_t k = j + 1; k < sample.size(); ++k)
      widest = std::max(widest, (s.points.col(sample[j]) - s.points.col(sample[k])).squaredNorm());
  return std::sqrt(widest);
}

/// The least distance between one of \a sample's points and one of \a other's.
double gap(const SegmentationState& s, const std::vector<int>& sample,
           const std::vector<int>& other) {
  double least = std::numeric_limits<double>::infinity();
  for (int j : sample)
    for (int k : other)
      least = std::min(least, (s.points.col(j) - s.points.col(k)).squaredNorm());
  return std::sqrt(least);
}

/// Whether region \a r's \a sample lies within T::union_noise_ratio times its noise of region \a
/// other's primitive (or times its own primitive's RMS, where that is worse): the other piece's
/// surface, extended, passes through this one.
bool predicts(const SegmentationState& s, std::size_t other, std::size_t r,
              const std::vector<int>& sample) {
  const double own = noiseRatio(s, sample, s.fits[r].refined);
  return noiseRatio(s, sample, s.fits[other].refined) <= T::union_noise_ratio * std::max(1.0, own);
}

}  // namespace

void mergeRegions(SegmentationState& s) {
  // Merge adjacent regions while the best fit of their union (any type: bands of a cone grown as
  // cylinders merge into the cone) is about as good as the parts.
  mergeAdjacent(s, false);
}

void mergeSettledRegions(SegmentationState& s) {
  // Boundaries and creases have settled: regions that the free crease points kept apart now touch.
  // Two adjacent regions merge when one primitive of the larger's type is the better model of
  // their union by BIC (unionIsSimpler). Not by the first merge's margin on the RMS: here, that
  // merged distinct shapes meeting at a crease (seed 6 of the 100k scenes at σ 0.5 %: 0.951 →
  // 0.929), and a plane took outlier specks one by one, each raising its RMS enough to admit the
  // next. Not into a new type: the union of a far office wall, bent by the sensor, and a strip
  // beside it was a sphere of radius 17.5 m.
  mergeAdjacent(s, true);
}

void joinOccludedPieces(SegmentationState& s) {
  // Seen by a sensor, one surface is cut into pieces by whatever stands in front of it: the floor
  // left and right of a table, a wall behind a post. No neighbor links the pieces, so no merge so
  // far has seen them as a pair. Two regions of one type that do not touch join when they lie no
  // further apart than the smaller is wide, each one's own primitive, extended, passes through the
  // other within its noise (predicts), and one primitive of their type, refined on both, explains
  // each within its noise (keepsWithinNoise) and, but for planes, is the better model of the two
  // by BIC (unionIsSimpler). BIC assumes independent errors; a sensor's are correlated over a
  // plane (depth levels, the bend of a camera's far rows), and on 10⁴–10⁵ points it read a
  // 4 mm offset between two pieces of the floor around a table as two planes (simulated close
  // frame, seed 2; the development frames' mean IoU 0.910 → 0.916 without it for planes). For
  // curved pieces it stays: two cups side by side, one cylinder explaining both within their
  // noise, are two cups (the same frame: a cup lost when BIC was dropped for every type).
  // Only on a sensor's frame: on a CAD part two coplanar faces apart are two faces (Fit4CAD's
  // ground truth has 250 such pairs of planes in 47 of its 188 parts).
  // Larger regions first, the larger taking the smaller; deterministic.
  if (!s.sensor_frame || s.noise.empty())
    return;
  std::vector<std::size_t> order;
  for (std::size_t r = 0; r < s.regions.size(); ++r)
    if (s.alive[r] && s.regions[r].size() >= s.result.min_points)
      order.push_back(r);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return s.regions[a].size() > s.regions[b].size();
  });
  const std::vector<std::set<std::size_t>> touching = s.touchingRegions();
  std::vector<std::vector<int>> samples(s.regions.size());
  std::vector<Eigen::AlignedBox3d> boxes(s.regions.size());
  const auto resample = [&](std::size_t r) {
    samples[r] = sampleOf(s.regions[r]);
    boxes[r].setEmpty();
    for (int i : samples[r])
      boxes[r].extend(s.points.col(i));
  };
  for (const std::size_t r : order)
    resample(r);
  std::vector<char> refreshed(s.regions.size(), 0);
  for (std::size_t i = 0; i < order.size(); ++i) {
    const std::size_t big = order[i];
    if (!s.alive[big])
      continue;
    for (std::size_t j = i + 1; j < order.size(); ++j) {
      const std::size_t small = order[j];
      // Not further apart than the smaller piece is wide (two boxes' fronts 1.6 m apart on a far
      // table, nearly coplanar, are two faces: simulated tabletop seed 2). The boxes first: the
      // gap is at least theirs, the extent at most the smaller box's diagonal.
      if (!s.alive[small] || s.fits[small].type != s.fits[big].type || touching[big].count(small) ||
          boxes[small].exteriorDistance(boxes[big]) > boxes[small].diagonal().norm() ||
          gap(s, samples[small], samples[big]) > extent(s, samples[small]))
        continue;
      // Each region's own fit, refreshed: boundaries moved since it was made.
      for (const std::size_t r : {big, small}) {
        if (refreshed[r])
          continue;
        FitResult own = s.grower->fitNear(s.fits[r].refined, s.regions[r]);
        if (own.ok() && own.type == s.fits[r].type)
          s.fits[r] = std::move(own);
        refreshed[r] = 1;
      }
      if (!predicts(s, big, small, samples[small]) || !predicts(s, small, big, samples[big]))
        continue;
      std::vector<int> both = s.regions[big];
      both.insert(both.end(), s.regions[small].begin(), s.regions[small].end());
      FitResult joint = s.grower->fitNear(s.fits[big].refined, both);
      if (!joint.ok() || joint.type != s.fits[big].type ||
          !keepsWithinNoise(s, big, small, joint.refined) ||
          (joint.type != PrimitiveType::plane && !unionIsSimpler(s, big, small, joint)))
        continue;
      s.moveInto(small, big);
      s.fits[big] = std::move(joint);
      resample(big);
      ++s.result.merges;
    }
  }
}

void absorbFragments(SegmentationState& s) {
  // One noisy surface can grow as several regions: where normals are unreliable (a Kinect's near
  // rows, whose depth steps are about its pixel spacing) growth stops, and the points left between
  // seed specks of their own that never touch the large region before creases are joined. A region
  // joins a neighbor T::dominates times its size when that neighbor's primitive explains its points
  // as well as it explains its own (RMS distance no larger): the neighbor's model does not change
  // and the small region is no better explained apart. Each pass decides on the regions as they
  // were before it (chains resolve to the largest), so the order of regions does not matter.
  for (int pass = 0; pass < T::absorb_passes; ++pass) {
    const std::vector<std::set<std::size_t>> touching = s.touchingRegions();
    std::vector<double> own(s.regions.size(), 0.0);
    for (std::size_t r = 0; r < s.regions.size(); ++r)
      if (s.alive[r])
        own[r] = s.rms(s.regions[r], s.fits[r].refined, nullptr);
    std::vector<std::ptrdiff_t> into(s.regions.size(), -1);
    bool any = false;
    for (std::size_t r = 0; r < s.regions.size(); ++r) {
      double best = std::numeric_limits<double>::infinity();
      for (const std::size_t b : touching[r]) {
        if (s.regions[b].size() < T::dominates * s.regions[r].size())
          continue;
        const double rms = s.rms(s.regions[r], s.fits[b].refined, nullptr);
        if (rms <= own[b] && rms < best) {
          best = rms;
          into[r] = static_cast<std::ptrdiff_t>(b);
        }
      }
      any = any || into[r] >= 0;
    }
    if (!any)
      return;
    for (std::size_t r = 0; r < s.regions.size(); ++r) {
      if (into[r] < 0)
        continue;
      auto target = static_cast<std::size_t>(into[r]);
      while (into[target] >= 0)
        target = static_cast<std::size_t>(into[target]);
      s.moveInto(r, target);
      ++s.result.absorbed;
    }
  }
}

}  // namespace slipfit::phases
