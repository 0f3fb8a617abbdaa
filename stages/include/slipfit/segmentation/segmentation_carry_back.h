#pragma once
/// \file From a segmentation of an analysis sample to a label for every input point (docs/
/// THEORY.md §6, "Large scans"): each input point takes, among the segments of its representative
/// (a kept point of the sample) and of the representative's neighbors, the one whose primitive is
/// nearest, when within the segmentation's tolerance at the point (SegmentationResult::tolerance:
/// the local step added on depth recorded on levels); otherwise −1. Where another is as
/// near within 2σ̂ and the two primitives' normals at the point are within the segmentation's
/// angle tolerance (a tangent junction, where one point's distances differ by r θ²/2 and cannot
/// choose), the one with the smaller mean signed distance over the input points of the
/// representative and its neighbors wins (the noise averaged over about k × (points per voxel)).
/// The segments' fits stay those of the sample; their members, RMS and largest distance are
/// recomputed on the input.

#include "slipfit/neighborhoods/neighborhoods.h"
#include "slipfit/segmentation/segmentation.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace slipfit {

/// \a points: 3 × N input coordinates (a float view with any column stride, as cloud_maps.h gives);
/// \a representative: per input point the index of its kept point in the sample, or −1;
/// \a sample_neighborhoods: the sample's neighborhoods; \a result: the sample's segmentation, whose
/// labels (per sample point) and segments are replaced by the input's. \a threads: 0 = all cores.
/// \a averaged: the sample's points are means of the input points they represent (voxel
/// centroids, representedMean), so their scatter — and the noise term of result.distance —
/// understates an input point's. The noise is then re-estimated on the input points (the median
/// distance to the nearest primitive around each, within 3 × the distance, over 0.6745, a
/// Gaussian's median |x|) and, when larger, result.noise and the distance's noise term
/// (result.noise_factor; none when the distance was given) take it.
/// Deterministic for any thread count. Throws DegenerateInputError on mismatched sizes.
void carrySegmentationBack(
    const Eigen::Ref<const Eigen::Matrix3Xf, 0, Eigen::OuterStride<>>& points,
    const std::vector<std::int32_t>& representative, const Neighborhoods& sample_neighborhoods,
    SegmentationResult& result, int threads = 0, bool averaged = false);

}  // namespace slipfit
