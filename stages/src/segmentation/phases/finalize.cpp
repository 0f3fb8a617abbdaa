// Phase 12 (drop_non_surfaces) and the end of the run: regions that are no surface dropped, and
// every segment refitted on all its members.
#include "phases.h"

#include "slipfit/segmentation/segmentation_tuning.h"
#include "slipfit/slippage/slippage.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace slipfit::phases {

namespace {

using T = SegmentationTuning;

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

/// The median over up to T::volume_thinness_sample of \a members (evenly spaced) of √(λ₀/λ₁),
/// the least two principal spreads of each one's neighborhood: small for points on a sheet.
double medianThinness(const SegmentationState& s, const std::vector<int>& members) {
  const std::size_t step = std::max<std::size_t>(1, members.size() / T::volume_thinness_sample);
  std::vector<double> thinness;
  for (std::size_t j = 0; j < members.size(); j += step) {
    const NeighborView hood = s.hood(members[j]);
    if (hood.size() < 4)
      continue;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (pcl::index_t k : hood)
      mean += s.points.col(k);
    mean /= static_cast<double>(hood.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (pcl::index_t k : hood) {
      const Eigen::Vector3d d = s.points.col(k) - mean;
      cov += d * d.transpose();
    }
    const Eigen::Vector3d lambda =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvalues();
    thinness.push_back(lambda(1) > 0.0 ? std::sqrt(std::max(0.0, lambda(0)) / lambda(1)) : 1.0);
  }
  if (thinness.empty())
    return 1.0;
  std::nth_element(thinness.begin(),
                   thinness.begin() + static_cast<std::ptrdiff_t>(thinness.size() / 2),
                   thinness.end());
  return thinness[thinness.size() / 2];
}

}  // namespace

void dropNonSurfaces(SegmentationState& s) {
  // A surface, not a volume: points spread uniformly through the slab |D| ≤ ε have an RMS
  // distance of ε/√3 ≈ 0.58 ε; a surface with Gaussian noise (ε = 3σ) about 0.33 ε, quantized
  // depth at most 0.29 ε (its error, uniform within ±step/2, fills half the slab), noise-free data
  // far less. A region above T::volume_ratio ε (each distance in units of its point's tolerance) is
  // random points that happen to lie within ε of some primitive (a cloud of noise): dropped.
  const RegionGrower& grower = *s.grower;
  const QuantizedAxis& lattice = s.result.lattice;
  const bool noisy = s.result.noise >= T::spacing_factor * s.spacing;
  for (std::size_t r = 0; r < s.regions.size(); ++r) {
    if (!s.alive[r])
      continue;
    const std::vector<int>& members = s.regions[r];
    double sum = 0.0;
    for (int i : members) {
      const double d = distance(s.points.col(i), s.fits[r].refined) / grower.tolerance(i);
      sum += d * d;
    }
    // With a quantized axis, a region all on one level is a slice of the sensor's lattice: its
    // shape along that axis is not measured.
    bool one_level = lattice.detected();
    for (std::size_t j = 1; one_level && j < members.size(); ++j)
      one_level = lattice.sameLevel(s.points.col(members[j]), s.points.col(members[0]));
    // On noise-free data (σ̂ below a twentieth of the spacing: CAD parts) a region that fills
    // its slab is a primitive fitted across what it does not explain, whatever its points'
    // neighborhoods: dropped as before.
    const bool fills_slab =
        std::sqrt(sum / static_cast<double>(members.size())) > T::volume_ratio &&
        (!noisy || medianThinness(s, members) >= T::volume_thinness);
    if (one_level || fills_slab) {
      s.drop(r);
      ++s.result.volumes;
    }
  }
}

SegmentationResult finalize(SegmentationState& s) {
  // Largest first, indices ascending; labels renumbered to match.
  const RegionGrower& grower = *s.grower;
  std::vector<std::size_t> order;
  for (std::size_t r = 0; r < s.regions.size(); ++r)
    if (s.alive[r])
      order.push_back(r);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    return s.regions[x].size() > s.regions[y].size();
  });
  SegmentationResult result = std::move(s.result);
  std::fill(result.labels.begin(), result.labels.end(), -1);
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::size_t r = order[k];
    Segment segment;
    segment.indices = std::move(s.regions[r]);
    std::sort(segment.indices.begin(), segment.indices.end());
    // Refit on the final members (crease points joined after the last fit), kept when it is no
    // worse than the region's fit: a face recovered with its own normals (phase 9) is refitted
    // here from the cloud's, which straddle its edges. Each member weighs by its precision
    // (RegionGrower::fitByPrecision): on a quantized scan the far rows, whose steps are several
    // times the near ones', no longer tilt a table.
    segment.fit = grower.fitByPrecision(s.fits[r].type, segment.indices);
    if (!segment.fit.ok() || s.precisionRms(segment.indices, segment.fit.refined) >
                                 s.precisionRms(segment.indices, s.fits[r].refined))
      segment.fit = std::move(s.fits[r]);
    segment.seed_type = s.seed_types[r];
    refineFromSlippage(s.points, s.normals, grower.precisionWeights(segment.indices), segment);
    segment.rms_distance = s.rms(segment.indices, segment.fit.refined, &segment.max_distance);
    for (int i : segment.indices)
      result.labels[static_cast<std::size_t>(i)] = static_cast<std::int32_t>(k);
    result.segments.push_back(std::move(segment));
  }
  s.regions.clear();
  s.fits.clear();
  s.seed_types.clear();
  s.alive.clear();
  return result;
}

}  // namespace slipfit::phases
