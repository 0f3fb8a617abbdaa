#pragma once
/// \file From a segmentation of an analysis sample to a label for every input point (docs/
/// THEORY.md §6, "Large scans"): each input point takes, among the segments of its representative
/// (a kept point of the sample) and of the representative's neighbors, the one whose primitive is
/// nearest, when within the segmentation's distance tolerance; otherwise −1. The segments' fits
/// stay those of the sample; their members, RMS and largest distance are recomputed on the input.

#include "slipfit/neighborhoods.h"
#include "slipfit/segmentation.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace slipfit {

/// \a points: 3 × N input coordinates (a float view with any column stride, as cloud_maps.h gives);
/// \a representative: per input point the index of its kept point in the sample, or −1;
/// \a sample_neighborhoods: the sample's neighborhoods; \a result: the sample's segmentation, whose
/// labels (per sample point) and segments are replaced by the input's. \a threads: 0 = all cores.
/// Deterministic for any thread count. Throws DegenerateInputError on mismatched sizes.
void carrySegmentationBack(
    const Eigen::Ref<const Eigen::Matrix3Xf, 0, Eigen::OuterStride<>>& points,
    const std::vector<std::int32_t>& representative, const Neighborhoods& sample_neighborhoods,
    SegmentationResult& result, int threads = 0);

}  // namespace slipfit
