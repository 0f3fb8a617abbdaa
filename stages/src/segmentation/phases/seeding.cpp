// Phases 2 and 3 (grow_slippage_seeds, grow_free_seeds): regions seeded and grown.
#include "phases.h"
#include "thin_wall.h"

#include "slipfit/fitting/model_selection.h"
#include "slipfit/segmentation/segmentation_tuning.h"

#include <algorithm>
#include <utility>

namespace slipfit::phases {

namespace {

using T = SegmentationTuning;

// Grows one region from \a members (a seed's neighborhood) with \a type; keeps it when it reaches
// min_points. \a seed_type is reported with the segment. With \a type_chosen (the type is already
// the simplest adequate one of the seed's neighborhood) a region that grows to fewer than
// min_points is dropped at once, without trying the other types.
void growRegion(SegmentationState& s, PrimitiveType type, std::vector<int> members,
                SlippageType seed_type, bool type_chosen) {
  RegionGrower& grower = *s.grower;
  if (static_cast<int>(members.size()) < minimumPoints(type) + 2)
    return;
  FitResult fit = grower.fit(type, members);
  if (!fit.ok())
    return;
  grower.prune(members, fit.refined);
  if (members.empty())
    return;
  ++s.result.regions_grown;
  fit = grower.grow(type, members, std::move(fit), s.result.labels);
  if (type_chosen && members.size() < s.result.min_points) {
    for (int i : members)
      s.tried[static_cast<std::size_t>(i)] = 1;
    return;
  }
  // The seed's local type can be wrong (a cone patch reads as a cylinder): refit the grown region
  // with the best type and, if it changes, grow again from the region with that type. The local
  // evidence stands unless another type fits clearly better, by the median distance (a BIC
  // margin, or the RMS, lets a wide sphere absorb the crease points of a plane).
  const double current = grower.medianDistance(members, fit.refined);
  FitResult best;
  if (current > s.result.noise)  // a Gaussian's median |d| is 0.67 σ: this model explains the data
    best = grower.fitBest(members);
  if (current > s.result.noise && best.ok() && best.type != type &&
      grower.medianDistance(members, best.refined) < T::retype_share * current) {
    grower.prune(members, best.refined);
    if (!members.empty())
      fit = grower.grow(best.type, members, std::move(best), s.result.labels);
  }
  FitResult final_fit = grower.fit(fit.type, members);
  if (final_fit.ok())
    fit = std::move(final_fit);
  grower.prune(members, fit.refined);
  for (int i : members)
    s.tried[static_cast<std::size_t>(i)] = 1;
  if (members.size() < s.result.min_points)
    return;
  // The seed's type fitted in its simpler limit (a cone of 0.06° whose apex lies 10⁴ sizes away
  // is a cylinder; isNearlyDegenerate) gives way to the simplest adequate type.
  if (fit.type != PrimitiveType::plane &&
      isNearlyDegenerate(fit.refined, s.points(Eigen::all, members))) {
    const FitResult simpler = grower.fitBest(members);
    FitResult refit = simpler.ok() ? grower.fit(simpler.type, members) : FitResult{};
    if (refit.ok())
      fit = std::move(refit);
  }
  s.addRegion(std::move(members), std::move(fit), seed_type);
}

}  // namespace

void growSlippageSeeds(SegmentationState& s) {
  // Seeds: points whose neighbors agree with their own primitive type, most agreement first
  // (ties by index: deterministic), grown with that type.
  std::vector<std::pair<int, int>> seeds;  // (−agreement, index)
  for (std::size_t i = 0; i < s.n; ++i) {
    if (!primitiveTypeOf(s.local_types[i]))
      continue;
    int agree = 0;
    for (pcl::index_t j : s.hoods[i])
      agree += s.local_types[static_cast<std::size_t>(j)] == s.local_types[i] ? 1 : 0;
    if (2 * agree > static_cast<int>(s.hoods[i].size()))
      seeds.emplace_back(-agree, static_cast<int>(i));
  }
  std::sort(seeds.begin(), seeds.end());
  for (const auto& [neg_agree, seed] : seeds) {
    const auto us = static_cast<std::size_t>(seed);
    if (s.result.labels[us] >= 0 || s.tried[us])
      continue;
    std::vector<int> members;
    for (pcl::index_t j : s.hoods[us])
      if (s.isFree(j) && s.local_types[static_cast<std::size_t>(j)] == s.local_types[us])
        members.push_back(j);
    s.tried[us] = 1;
    growRegion(s, *primitiveTypeOf(s.local_types[us]), std::move(members), s.local_types[us],
               false);
  }
}

void growFreeSeeds(SegmentationState& s) {
  // What is left — small faces whose neighborhoods straddle an edge, so that no point has an
  // agreeing local type — is seeded from every unlabelled point in index order, with the simplest
  // adequate type of its unlabelled neighbors.
  RegionGrower& grower = *s.grower;
  std::fill(s.tried.begin(), s.tried.end(), 0);
  // Outliers scattered through the volume have free neighborhoods too: a seed's must be sampled
  // like the regions of the first round around it (THEORY §6, phase 9).
  const std::vector<double> seeded_spacing = s.regionSpacings();
  std::vector<std::uint32_t> stamp(s.n, 0);
  std::uint32_t generation = 0;
  for (std::size_t us = 0; us < s.n; ++us) {
    if (s.result.labels[us] >= 0 || s.tried[us])
      continue;
    s.tried[us] = 1;
    std::vector<int> members;
    for (pcl::index_t j : s.hoods[us])
      if (s.isFree(j))
        members.push_back(j);
    if (4 * members.size() < 3 * s.hoods[us].size())
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
      for (pcl::index_t j : s.hood(m))
        if (s.isFree(j))
          ring2.push_back(j);
    std::sort(ring2.begin(), ring2.end());
    ring2.erase(std::unique(ring2.begin(), ring2.end()), ring2.end());
    if (!(start.ok() && start.rms_distance <= seed_tolerance)) {
      // A thin wall: the seed's sheet of the 2-ring, apart from the other sheet by a gap no noise
      // opens (T::sheet_gap tolerances), is the seed's neighborhood.
      std::vector<int> sheet =
          seedSheet(s.points, s.normals.col(static_cast<Eigen::Index>(us)), static_cast<int>(us),
                    ring2, T::sheet_gap * seed_tolerance);
      if (sheet.size() >= T::smallest_patch) {
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
      holds = !s.isScattered(members, seeded_spacing, stamp, generation);
    if (!holds) {
      // No surface here (outliers, or an edge): none of these points seeds again.
      for (int j : members)
        s.tried[static_cast<std::size_t>(j)] = 1;
      continue;
    }
    growRegion(s, start.type, std::move(members), s.local_types[us], true);
  }
}

}  // namespace slipfit::phases
