// Phase 5 (revise_types): a narrow region's type chosen again on the points it contests.
#include "phases.h"

#include "slipfit/core/angle_units.h"
#include "slipfit/core/median.h"
#include "slipfit/fitting/model_selection.h"
#include "slipfit/segmentation/segmentation_tuning.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <optional>

namespace slipfit::phases {

namespace {

using T = SegmentationTuning;

/// The contested points of region \a r: other regions' points within two rings of it. \a stamp
/// marks them with a fresh \a generation.
std::vector<int> contestedPoints(const SegmentationState& s, std::size_t r,
                                 std::vector<std::uint32_t>& stamp, std::uint32_t& generation) {
  const auto own = static_cast<std::int32_t>(r);
  ++generation;
  std::vector<int> ring;
  const auto take = [&](int i) {
    for (pcl::index_t j : s.hood(i)) {
      const auto uj = static_cast<std::size_t>(j);
      if (s.label(j) >= 0 && s.label(j) != own && stamp[uj] != generation) {
        stamp[uj] = generation;
        ring.push_back(j);
      }
    }
  };
  for (int i : s.regions[r])
    take(i);
  for (std::size_t k = 0, first = ring.size(); k < first; ++k)
    take(ring[k]);
  return ring;
}

/// A torus whose circle of tube centres bends over \a points by less than \a noise: the sagitta
/// R (1 − cos(Δφ/2)) of the arc of angle Δφ the points span about its axis. Such a torus is its
/// cylinder limit to within the noise, whatever its RMS: fitted to a band of a fillet it takes
/// the rows of the planes on either side by tilting its tube along the band (a band of 34 points
/// of a 0.064 fillet, σ 0.0025: R 1.39, r 0.080, sagitta 0.0020).
bool bendsWithinNoise(const Torus& torus, const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                      double noise) {
  const Eigen::Vector3d axis = torus.axis.normalized();
  const Eigen::Vector3d mean = points.rowwise().mean();
  Eigen::Vector3d e1 = (mean - torus.center) - (mean - torus.center).dot(axis) * axis;
  if (!(e1.norm() > 0.0))
    return false;  // the points' centroid on the axis: they surround it
  e1.normalize();
  const Eigen::Vector3d e2 = axis.cross(e1);
  double lo = 0.0, hi = 0.0;  // angles about the axis, from the centroid's direction
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    const Eigen::Vector3d d = points.col(i) - torus.center;
    const double phi = std::atan2(d.dot(e2), d.dot(e1));
    lo = std::min(lo, phi);
    hi = std::max(hi, phi);
  }
  const double span = hi - lo;
  return span < kPi && torus.major_radius * (1.0 - std::cos(0.5 * span)) < noise;
}

}  // namespace

void reviseTypes(SegmentationState& s) {
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
  RegionGrower& grower = *s.grower;
  const double sigma2 = s.result.noise * s.result.noise + s.edge_margin * s.edge_margin;
  const auto medianAngle = [&](const std::vector<int>& members, const Primitive& primitive) {
    std::vector<double> angles;
    for (std::size_t m = 0; m < members.size(); m += 1 + members.size() / 512)
      angles.push_back(s.normalAngle(members[m], primitive));
    return quantile(angles, 0.5);
  };
  std::vector<std::uint32_t> stamp(s.n, 0);
  std::uint32_t generation = 0;
  for (std::size_t r = 0; r < s.regions.size(); ++r) {
    if (!s.alive[r] || s.regions[r].size() < s.result.min_points)
      continue;
    const std::vector<int>& members = s.regions[r];
    const std::vector<int> ring = contestedPoints(s, r, stamp, generation);
    if (ring.empty())
      continue;
    // A wide region's own points decide its type, unless its normals turn: a fillet's middle band
    // can be flat to within the noise of distances and still turn its normals by tens of degrees.
    const bool wide = ring.size() < members.size();
    const double own_angle = wide ? medianAngle(members, s.fits[r].refined) : 0.0;
    std::vector<double> held(ring.size());  // each contested point's capped d² to its own
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const double t = grower.tolerance(ring[k]);
      const Primitive& theirs = s.fits[static_cast<std::size_t>(s.label(ring[k]))].refined;
      held[k] = std::min(t * t, std::pow(distance(s.points.col(ring[k]), theirs), 2));
    }
    // The contested points' capped squared distances with the candidate, and how many it takes.
    const auto contest = [&](const Primitive& candidate, std::size_t& taken) {
      double sum = 0.0;
      taken = 0;
      for (std::size_t k = 0; k < ring.size(); ++k) {
        double d2 = held[k];
        if (grower.accepts(ring[k], candidate)) {
          const double c2 = std::pow(distance(s.points.col(ring[k]), candidate), 2);
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
    double best =
        contest(s.fits[r].refined, taken) + parameterCount(s.fits[r].type) * sigma2 * log_n;
    const Eigen::Matrix3Xd own_points = s.points(Eigen::all, members);
    std::optional<FitResult> choice;
    for (const auto& [type, name] : kPrimitiveTypeNames) {
      if (type == s.fits[r].type)
        continue;
      FitResult fit = grower.screen(type, members);
      if (!fit.ok() || isNearlyDegenerate(fit.refined, own_points) ||
          fit.rms_distance > (1.0 + kAdequacyMargin) * s.fits[r].rms_distance)
        continue;
      if (const auto* torus = std::get_if<Torus>(&fit.refined);
          torus && bendsWithinNoise(*torus, own_points, std::sqrt(sigma2)))
        continue;
      if (wide && !(T::normal_turn_ratio * medianAngle(members, fit.refined) < own_angle))
        continue;
      const double c = contest(fit.refined, taken) + parameterCount(type) * sigma2 * log_n;
      if (c < best && taken >= 3 * static_cast<std::size_t>(parameterCount(type))) {
        best = c;
        choice = std::move(fit);
      }
    }
    if (choice) {
      // Chosen on kTypeSubset members (as fitBest chooses), refitted on up to kSubset.
      if (FitResult refit = grower.fit(choice->type, members); refit.ok())
        choice = std::move(refit);
      s.fits[r] = std::move(*choice);
      ++s.result.revised;
    }
  }
}

}  // namespace slipfit::phases
