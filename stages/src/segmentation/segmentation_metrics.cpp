#include "slipfit/segmentation/segmentation_metrics.h"

#include "slipfit/core/exceptions.h"

#include <algorithm>
#include <limits>

namespace slipfit {

std::vector<int> maximumAssignment(const std::vector<double>& weights, std::size_t rows,
                                   std::size_t cols) {
  // Kuhn–Munkres with potentials (shortest augmenting paths) on the square cost matrix
  // max − w, padded with zero-weight rows or columns.
  const std::size_t n = std::max(rows, cols);
  double top = 0.0;
  for (double w : weights)
    top = std::max(top, w);
  auto cost = [&](std::size_t r, std::size_t c) {
    return r < rows && c < cols ? top - weights[r * cols + c] : top;
  };
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(n + 1, 0.0), v(n + 1, 0.0);
  std::vector<std::size_t> p(n + 1, 0), way(n + 1, 0);  // p[c]: row matched to column c (1-based)
  for (std::size_t r = 1; r <= n; ++r) {
    p[0] = r;
    std::size_t c0 = 0;
    std::vector<double> minv(n + 1, inf);
    std::vector<char> used(n + 1, 0);
    do {
      used[c0] = 1;
      const std::size_t r0 = p[c0];
      double delta = inf;
      std::size_t c1 = 0;
      for (std::size_t c = 1; c <= n; ++c)
        if (!used[c]) {
          const double cur = cost(r0 - 1, c - 1) - u[r0] - v[c];
          if (cur < minv[c]) {
            minv[c] = cur;
            way[c] = c0;
          }
          if (minv[c] < delta) {
            delta = minv[c];
            c1 = c;
          }
        }
      for (std::size_t c = 0; c <= n; ++c) {
        if (used[c]) {
          u[p[c]] += delta;
          v[c] -= delta;
        } else {
          minv[c] -= delta;
        }
      }
      c0 = c1;
    } while (p[c0] != 0);
    do {
      const std::size_t c1 = way[c0];
      p[c0] = p[c1];
      c0 = c1;
    } while (c0 != 0);
  }
  std::vector<int> match(rows, -1);
  for (std::size_t c = 1; c <= n; ++c)
    if (p[c] >= 1 && p[c] <= rows && c <= cols)
      match[p[c] - 1] = static_cast<int>(c - 1);
  return match;
}

SegmentationScore scoreSegmentation(const std::vector<std::int32_t>& truth,
                                    const std::vector<std::int32_t>& predicted,
                                    const std::vector<int>& truth_types,
                                    const std::vector<int>& predicted_types) {
  if (truth.size() != predicted.size())
    throw DegenerateInputError("segmentation score: truth and prediction differ in length");
  SegmentationScore s;
  std::int32_t tmax = -1, pmax = -1;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    tmax = std::max(tmax, truth[i]);
    pmax = std::max(pmax, predicted[i]);
  }
  s.truths = static_cast<std::size_t>(tmax + 1);
  s.segments = static_cast<std::size_t>(pmax + 1);
  std::vector<double> both(s.truths * s.segments, 0.0), tsize(s.truths, 0.0),
      psize(s.segments, 0.0);
  std::size_t surface = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (truth[i] >= 0) {
      ++surface;
      tsize[static_cast<std::size_t>(truth[i])] += 1;
    }
    if (predicted[i] >= 0)
      psize[static_cast<std::size_t>(predicted[i])] += 1;
    if (truth[i] >= 0 && predicted[i] >= 0)
      both[static_cast<std::size_t>(truth[i]) * s.segments +
           static_cast<std::size_t>(predicted[i])] += 1;
  }
  std::vector<double> iou(both.size(), 0.0);
  for (std::size_t t = 0; t < s.truths; ++t)
    for (std::size_t k = 0; k < s.segments; ++k) {
      const double inter = both[t * s.segments + k];
      const double uni = tsize[t] + psize[k] - inter;
      iou[t * s.segments + k] = uni > 0 ? inter / uni : 0.0;
    }
  s.match = maximumAssignment(iou, s.truths, s.segments);
  s.iou.assign(s.truths, 0.0);
  double right_points = 0.0;
  std::size_t typed = 0, right_types = 0;
  for (std::size_t t = 0; t < s.truths; ++t) {
    const int k = s.match[t];
    if (k < 0 || iou[t * s.segments + static_cast<std::size_t>(k)] <= 0.0) {
      s.match[t] = -1;
      continue;
    }
    s.iou[t] = iou[t * s.segments + static_cast<std::size_t>(k)];
    right_points += both[t * s.segments + static_cast<std::size_t>(k)];
    if (t < truth_types.size() && static_cast<std::size_t>(k) < predicted_types.size()) {
      ++typed;
      right_types += truth_types[t] == predicted_types[static_cast<std::size_t>(k)] ? 1 : 0;
    }
  }
  // A label no point carries is not a true primitive of this cloud (a surface the sensor did not
  // see): it is neither counted nor scored.
  std::size_t present = 0;
  for (std::size_t t = 0; t < s.truths; ++t)
    if (tsize[t] > 0) {
      s.mean_iou += s.iou[t];
      ++present;
    }
  s.truths = present;
  s.mean_iou = present ? s.mean_iou / static_cast<double>(present) : 0.0;
  s.point_accuracy = surface ? right_points / static_cast<double>(surface) : 0.0;
  s.type_accuracy = typed ? static_cast<double>(right_types) / static_cast<double>(typed) : 0.0;
  return s;
}

}  // namespace slipfit
