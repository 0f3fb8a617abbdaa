#pragma once
/// \file Scores of a segmentation against ground-truth labels: segments matched one-to-one to
/// the true primitives by the Hungarian method on their IoU, then mean IoU, per-point accuracy and
/// type accuracy — the measures of the segmentation benchmark.

#include <cstdint>
#include <vector>

namespace slipfit {

struct SegmentationScore {
  /// Over the true primitives that have points (unmatched ones count 0; a label without points
  /// is not counted).
  double mean_iou = 0.0;
  double point_accuracy = 0.0;  ///< surface points in the segment matched to their primitive
  double type_accuracy = 0.0;   ///< matched segments whose type is the true primitive's
  std::size_t truths = 0;       ///< true primitives with points (labels >= 0)
  std::size_t segments = 0;     ///< predicted segments (labels >= 0)
  /// match[t] = the predicted label matched to true label t, or −1.
  std::vector<int> match;
  std::vector<double> iou;  ///< per true label
};

/// Maximum-weight one-to-one assignment of rows to columns (Hungarian method, O(n³)) on a dense
/// rows × cols weight matrix stored row-major; returns for each row its column or −1.
std::vector<int> maximumAssignment(const std::vector<double>& weights, std::size_t rows,
                                   std::size_t cols);

/// \a truth and \a predicted: per-point labels (−1: outlier / unassigned), same length.
/// \a truth_types and \a predicted_types: a type code per label (any integer coding), used for the
/// type accuracy; may be empty to skip it.
SegmentationScore scoreSegmentation(const std::vector<std::int32_t>& truth,
                                    const std::vector<std::int32_t>& predicted,
                                    const std::vector<int>& truth_types = {},
                                    const std::vector<int>& predicted_types = {});

}  // namespace slipfit
