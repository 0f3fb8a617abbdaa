// Phase 6 (recover_fillets): a fillet that two planes took whole as they grew, given back to a
// cylinder of its own.
#include "phases.h"

#include "slipfit/segmentation/crease_fillet.h"
#include "slipfit/segmentation/segmentation_tuning.h"

#include <algorithm>
#include <cmath>
#include <set>

namespace slipfit::phases {

namespace {

using T = SegmentationTuning;

/// Region \a r's plane when it is a live plane region of at least min_points, else null.
const Plane* planeOf(const SegmentationState& s, std::size_t r) {
  return s.alive[r] && s.regions[r].size() >= s.result.min_points
             ? std::get_if<Plane>(&s.fits[r].refined)
             : nullptr;
}

/// The pairs (a < b) of plane regions that touch, or meet across one free point.
std::set<std::pair<std::size_t, std::size_t>> touchingPlanes(const SegmentationState& s) {
  std::set<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t r = 0; r < s.regions.size(); ++r) {
    if (!planeOf(s, r))
      continue;
    auto note = [&](int other) {
      if (other >= 0 && static_cast<std::size_t>(other) > r &&
          planeOf(s, static_cast<std::size_t>(other)))
        pairs.emplace(r, static_cast<std::size_t>(other));
    };
    for (int i : s.regions[r])
      for (pcl::index_t j : s.hood(i)) {
        const int lj = s.label(j);
        if (lj >= 0) {
          note(lj);
          continue;
        }
        for (pcl::index_t k : s.hood(j))
          note(s.label(k));
      }
  }
  return pairs;
}

/// The band of the crease: the members of regions \a a and \a b and their free neighbours no
/// further from the crease line than \a band plus three tolerances; ascending, unique.
std::vector<int> creaseBand(const SegmentationState& s, std::size_t a, std::size_t b,
                            const CreaseSection& section, double band) {
  const RegionGrower& grower = *s.grower;
  std::vector<int> near;
  auto inBand = [&](int i) {
    Eigen::Vector3d q = s.points.col(i) - section.origin;
    q -= section.along.dot(q) * section.along;
    return q.norm() <= band + 3.0 * grower.tolerance(i);
  };
  for (std::size_t r : {a, b})
    for (int i : s.regions[r])
      if (inBand(i)) {
        near.push_back(i);
        for (pcl::index_t j : s.hood(i))
          if (s.isFree(j) && inBand(j))
            near.push_back(j);
      }
  std::sort(near.begin(), near.end());
  near.erase(std::unique(near.begin(), near.end()), near.end());
  return near;
}

/// Tries a fillet between the planes of regions \a a and \a b; adds it as a cylinder region and
/// refits the planes without its points when the data demand it.
void tryFillet(SegmentationState& s, std::size_t a, std::size_t b) {
  RegionGrower& grower = *s.grower;
  const double crease_cos = std::cos(s.result.max_angle);
  const Plane* pa = planeOf(s, a);
  const Plane* pb = planeOf(s, b);
  if (!pa || !pb || std::abs(pa->normal.dot(pb->normal)) > crease_cos)
    return;
  const std::optional<CreaseSection> section = creaseSection(
      *pa, *pb, s.points(Eigen::all, s.regions[a]), s.points(Eigen::all, s.regions[b]));
  if (!section)
    return;
  // The largest radius puts the tangent points halfway across the narrower plane; the smallest
  // is twice the tolerance (a fillet within it is an edge).
  auto reach = [&](const std::vector<int>& members, const Eigen::Vector3d& u) {
    double most = 0.0;
    for (int i : members)
      most = std::max(most, u.dot(s.points.col(i) - section->origin));
    return most;
  };
  const double half = 0.5 * section->opening;
  const double largest =
      0.5 * std::min(reach(s.regions[a], section->ua), reach(s.regions[b], section->ub)) *
      std::tan(half);
  const double smallest = 2.0 * std::max(grower.smallestTolerance(s.regions[a]),
                                         grower.smallestTolerance(s.regions[b]));
  if (!(largest > smallest))
    return;
  // The band: no further from the crease than the largest fillet's tangent points.
  const std::vector<int> near = creaseBand(s, a, b, *section, largest / std::tan(half));
  // The radius is chosen on at most T::fillet_sample of them (evenly strided).
  const std::size_t stride = 1 + near.size() / T::fillet_sample;
  std::vector<int> sample;
  for (std::size_t k = 0; k < near.size(); k += stride)
    sample.push_back(near[k]);
  Eigen::VectorXd sigma(static_cast<Eigen::Index>(sample.size()));
  for (std::size_t k = 0; k < sample.size(); ++k)
    sigma(static_cast<Eigen::Index>(k)) = grower.tolerance(sample[k]) / T::noise_factor;
  const FilletChoice choice =
      chooseFilletRadius(*section, s.points(Eigen::all, sample), sigma, smallest, largest);
  const double n = static_cast<double>(sample.size());
  if (!(choice.radius > 0.0) ||
      choice.sharp_cost - choice.cost <= T::fillet_parameters * std::log(n) ||
      choice.on_arc * stride < s.result.min_points)
    return;
  std::vector<int> arc;
  for (int i : near) {
    double d = 0.0;
    if (filletDistance(*section, choice.radius, s.points.col(i), &d) == FilletPiece::arc &&
        d <= grower.tolerance(i))
      arc.push_back(i);
  }
  if (arc.size() < s.result.min_points)
    return;
  FitResult fit = grower.fit(PrimitiveType::cylinder, arc);
  const auto* cylinder = std::get_if<Cylinder>(&fit.refined);
  if (!fit.ok() || !cylinder || std::abs(cylinder->axis.dot(section->along)) < crease_cos ||
      cylinder->radius > 2.0 * choice.radius || cylinder->radius < 0.5 * choice.radius)
    return;
  ++s.result.fillets;
  s.addRegion(arc, std::move(fit), SlippageType::cylinder);
  for (std::size_t r : {a, b}) {
    const auto label = static_cast<std::int32_t>(r);
    auto& members = s.regions[r];
    members.erase(
        std::remove_if(members.begin(), members.end(), [&](int i) { return s.label(i) != label; }),
        members.end());
    FitResult refit = grower.fit(PrimitiveType::plane, members);
    if (refit.ok())
      s.fits[r] = std::move(refit);
  }
}

}  // namespace

void recoverFillets(SegmentationState& s) {
  // A fillet of radius r between two planes lies within ε of them except its middle rows, up to
  // r (1 − sin(opening / 2)) off both: at r ≈ 20 σ the planes take it all as they grow (THEORY §6,
  // phase 6). For each pair of plane regions that touch (or meet across one free point) at a
  // crease, the cross-section's fillet radius is fitted on the points near the crease, and the
  // fillet is kept when its gain over the sharp crease (in squared σ) beats its parameters' cost
  // by the Bayesian information criterion and its arc holds min_points.
  if (!s.parameters.fillets)
    return;
  for (const auto& [a, b] : touchingPlanes(s))
    tryFillet(s, a, b);
}

}  // namespace slipfit::phases
