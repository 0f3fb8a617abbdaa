// Phases 4, 10 and 11 (merge_regions, absorb_fragments, merge_settled_regions): adjacent
// regions joined when one primitive explains them together.
#include "phases.h"

#include "slipfit/fitting/model_selection.h"
#include "slipfit/segmentation/segmentation_tuning.h"

#include <omp.h>

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

/// Whether the merge accepts \a fit as the primitive of regions a and b together: its RMS distance
/// at most merge_factor × the larger of the two regions' (two planes at a crease: below both),
/// or, \a settled, unionIsSimpler; or within their noise (explainsWithinNoise).
bool acceptsUnion(const SegmentationState& s, std::size_t a, std::size_t b, const FitResult& fit,
                  bool settled) {
  if (!fit.ok())
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
