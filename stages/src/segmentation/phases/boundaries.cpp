// Phases 7 and 8 (refine_boundaries, join_creases): points move to the segment whose primitive
// explains them best, and free points at creases join an adjacent one.
#include "phases.h"

#include "slipfit/core/median.h"
#include "slipfit/fitting/model_selection.h"
#include "slipfit/segmentation/segmentation_tuning.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace slipfit::phases {

namespace {

using T = SegmentationTuning;

/// Decides where a labelled point belongs among its own segment and its neighbors'.
class BoundaryJudge {
 public:
  explicit BoundaryJudge(const SegmentationState& s) : s_(s) {
    // The normal noise: the median angle between members' normals and their primitive's (a
    // Rayleigh median is 1.177 σ_θ).
    std::vector<double> angles;
    for (std::size_t r = 0; r < s.regions.size(); ++r)
      if (s.alive[r])
        for (std::size_t m = 0; m < s.regions[r].size(); m += 7)
          angles.push_back(s.normalAngle(s.regions[r][m], s.fits[r].refined));
    sigma_angle_ = angles.empty() ? 1.0 : std::max(quantile(angles, 0.5) / 1.177, 1e-3);
    sigma_distance_ = std::sqrt(s.result.noise * s.result.noise + s.edge_margin * s.edge_margin);
  }

  /// The cost of \a primitive at point i: its neighborhood's mean signed distance (at a tangent
  /// junction the other primitive's bias r θ²/2 is one-signed and survives the mean while the
  /// noise shrinks by √k) in units of the noise of that mean, and the angle of the point's normal.
  double cost(int i, const Primitive& primitive) const {
    const Eigen::Vector3d p = s_.points.col(i);
    double sum = signedDistance(p, primitive);
    for (pcl::index_t j : s_.hood(i))
      sum += signedDistance(s_.points.col(j), primitive);
    const double count = static_cast<double>(s_.hood(i).size() + 1);
    const double mean = sum / count / (sigma_distance_ / std::sqrt(count));
    const double angle = s_.normalAngle(i, primitive) / sigma_angle_;
    return mean * mean + angle * angle;
  }

  /// The segment point \a i (labelled) belongs to: the nearest of its own and its neighbors'
  /// segments that accept it, unless another is as near within the noise: then the neighborhood
  /// decides (cost), and the point stays unless another is better by T::stay_cost (a tie of noisy
  /// normals would otherwise let a segment creep a ring per pass).
  std::int32_t choose(int i) const {
    const RegionGrower& grower = *s_.grower;
    const std::int32_t own = s_.label(i);
    std::array<std::int32_t, 8> candidates{own};
    std::array<double, 8> d{};
    std::size_t count = 1;
    for (pcl::index_t j : s_.hood(i)) {
      const std::int32_t other = s_.label(j);
      if (other < 0 || count == candidates.size() ||
          std::find(candidates.begin(), candidates.begin() + count, other) !=
              candidates.begin() + count ||
          !grower.accepts(i, s_.primitive(other)))
        continue;
      candidates[count++] = other;
    }
    if (count == 1)
      return own;
    const Eigen::Vector3d p = s_.points.col(i);
    std::size_t nearest = 0;
    for (std::size_t c = 0; c < count; ++c) {
      d[c] = distance(p, s_.primitive(candidates[c]));
      if (d[c] < d[nearest])
        nearest = c;
    }
    const double margin = T::tie_share * grower.tolerance(i);
    std::size_t choice = nearest;
    std::size_t close = 0;
    for (std::size_t c = 0; c < count; ++c)
      close += d[c] <= d[nearest] + margin ? 1 : 0;
    if (close > 1) {
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t c = 0; c < count; ++c)
        if (d[c] <= d[nearest] + margin) {
          const double e = cost(i, s_.primitive(candidates[c])) - (c == 0 ? T::stay_cost : 0.0);
          if (e < best) {
            best = e;
            choice = c;
          }
        }
    }
    return candidates[choice];
  }

 private:
  const SegmentationState& s_;
  double sigma_angle_ = 1.0;
  double sigma_distance_ = 0.0;
};

/// A point that two adjacent primitives explain equally well — both within its tolerance, their
/// distances within the floor of noise-free data (s/20: no measurement tells them apart) — lies
/// on their edge: it belongs to both, and its label goes to the smaller segment, whose share of
/// it is the larger (the Dice-optimal tie: Fit4CAD labels such points with both faces). With
/// noise the nearest primitive keeps them (a margin of σ̂ cost the 100k scenes 0.013 of IoU).
void shareEdges(SegmentationState& s) {
  const RegionGrower& grower = *s.grower;
  std::vector<std::size_t> size(s.regions.size());
  for (std::size_t r = 0; r < s.regions.size(); ++r)
    size[r] = s.regions[r].size();
  std::vector<std::pair<int, std::int32_t>> moves;
  for (int i = 0; i < static_cast<int>(s.n); ++i) {
    const std::int32_t own = s.label(i);
    if (own < 0)
      continue;
    const Eigen::Vector3d p = s.points.col(i);
    const double tolerance = grower.tolerance(i);
    const double tie = distance(p, s.primitive(own)) + s.edge_margin;
    std::int32_t label = own;
    for (pcl::index_t j : s.hood(i)) {
      const std::int32_t other = s.label(j);
      if (other < 0 || other == label ||
          size[static_cast<std::size_t>(other)] >= size[static_cast<std::size_t>(label)])
        continue;
      const double d = distance(p, s.primitive(other));
      if (d <= tolerance && d <= tie)
        label = other;
    }
    if (label != own)
      moves.emplace_back(i, label);
  }
  for (const auto& [i, label] : moves)
    s.label(i) = label;
  if (!moves.empty())
    s.relabelFromRegions();
}

}  // namespace

void refineBoundaries(SegmentationState& s) {
  // A point that the neighboring segment's primitive explains better than its own moves there — a
  // plane that took the first rows of a tangent fillet gives them back. Better: nearer (within ε,
  // normal within α); where two primitives are within 2σ̂ of each other at the point (a tangent
  // junction: a fillet point θ from the tangent line is r θ²/2 off the plane), by the cost of
  // BoundaryJudge, which averages the noise over the neighborhood and adds the normal's angle
  // (linear in θ, not quadratic). Up to T::boundary_passes passes, each on refits of the regions
  // that changed, while the moves settle (T::settling). Edge points then go to the smaller
  // segment (shareEdges).
  RegionGrower& grower = *s.grower;
  std::vector<char> changed(s.regions.size(), 0);
  const BoundaryJudge judge(s);
  std::size_t previous_moves = 0;
  for (int pass = 0; pass < T::boundary_passes; ++pass) {
    for (std::size_t r = 0; r < s.regions.size(); ++r)
      if (s.alive[r] && changed[r]) {
        FitResult refit = grower.fit(s.fits[r].type, s.regions[r]);
        if (refit.ok())
          s.fits[r] = std::move(refit);
      }
    std::vector<std::pair<int, std::int32_t>> moves;
    for (int i = 0; i < static_cast<int>(s.n); ++i) {
      if (s.isFree(i))
        continue;
      const std::int32_t label = judge.choose(i);
      if (label != s.label(i))
        moves.emplace_back(i, label);
    }
    // A boundary settling moves fewer points each pass; a segment creeping into its neighbor
    // (refitted on what it took, it takes the next ring: noisy depth at a table's rim) does not.
    if (moves.empty() || (pass >= 2 && static_cast<double>(moves.size()) >
                                           T::settling * static_cast<double>(previous_moves)))
      break;
    previous_moves = moves.size();
    for (const auto& [i, label] : moves) {
      changed[static_cast<std::size_t>(s.label(i))] = 1;
      changed[static_cast<std::size_t>(label)] = 1;
      s.label(i) = label;
    }
    s.relabelFromRegions();
    for (std::size_t r = 0; r < s.regions.size(); ++r)
      if (s.alive[r] &&
          s.regions[r].size() < static_cast<std::size_t>(minimumPoints(s.fits[r].type)))
        s.drop(r);
  }
  shareEdges(s);
}

void joinCreases(SegmentationState& s) {
  // Points left over at creases (where estimated normals blur) join an adjacent region whose
  // primitive is within their distance tolerance (the normal test is waived): the nearest, or of
  // several as near (within s/20) the smallest (see shareEdges).
  const RegionGrower& grower = *s.grower;
  for (int pass = 0, assigned = 1; assigned && pass < 2; ++pass) {
    assigned = 0;
    std::vector<std::pair<int, std::int32_t>> joins;
    for (int i = 0; i < static_cast<int>(s.n); ++i) {
      if (!s.isFree(i))
        continue;
      const Eigen::Vector3d p = s.points.col(i);
      const double tolerance = grower.tolerance(i);
      double nearest = tolerance;
      for (pcl::index_t j : s.hood(i))
        if (s.label(j) >= 0)
          nearest = std::min(nearest, distance(p, s.primitive(s.label(j))));
      std::int32_t label = -1;
      for (pcl::index_t j : s.hood(i)) {
        const std::int32_t other = s.label(j);
        if (other < 0 || other == label || (label >= 0 && s.size(other) >= s.size(label)))
          continue;
        const double d = distance(p, s.primitive(other));
        if (d <= tolerance && d <= nearest + s.edge_margin)
          label = other;
      }
      if (label >= 0)
        joins.emplace_back(i, label);
    }
    for (const auto& [i, label] : joins) {
      s.label(i) = label;
      s.regions[static_cast<std::size_t>(label)].push_back(i);
      assigned = 1;
    }
  }
}

}  // namespace slipfit::phases
