#include "slipfit/tiling/segment_joining.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace slipfit {

namespace {
void checkAscending(const std::vector<std::uint64_t>& rows, std::size_t labels, const char* tile) {
  if (rows.size() != labels)
    throw std::invalid_argument(std::string("tile ") + tile + ": rows and labels differ in length");
  for (std::size_t k = 1; k < rows.size(); ++k)
    if (rows[k] <= rows[k - 1])
      throw std::invalid_argument(std::string("tile ") + tile + ": rows are not ascending at " +
                                  std::to_string(k));
}
}  // namespace

OverlapCounts countOverlap(const std::vector<std::uint64_t>& rows_a,
                           const std::vector<std::int32_t>& labels_a,
                           const std::vector<std::uint64_t>& rows_b,
                           const std::vector<std::int32_t>& labels_b) {
  checkAscending(rows_a, labels_a.size(), "A");
  checkAscending(rows_b, labels_b.size(), "B");
  OverlapCounts c;
  std::size_t p = 0, q = 0;
  while (p < rows_a.size() && q < rows_b.size()) {
    if (rows_a[p] < rows_b[q]) {
      ++p;
    } else if (rows_b[q] < rows_a[p]) {
      ++q;
    } else {
      ++c.shared;
      const std::int32_t a = labels_a[p], b = labels_b[q];
      if (a >= 0)
        ++c.in_a[a];
      if (b >= 0)
        ++c.in_b[b];
      if (a >= 0 && b >= 0)
        ++c.both[{a, b}];
      ++p;
      ++q;
    }
  }
  return c;
}

std::vector<std::pair<std::int32_t, std::int32_t>> segmentsToJoin(const OverlapCounts& counts,
                                                                  const std::vector<int>& type_a,
                                                                  const std::vector<int>& type_b,
                                                                  const JoinParameters& p) {
  std::vector<std::pair<std::int32_t, std::int32_t>> joins;
  for (const auto& [pair, together] : counts.both) {
    const auto [a, b] = pair;
    if (static_cast<std::size_t>(a) >= type_a.size() ||
        static_cast<std::size_t>(b) >= type_b.size() ||
        type_a[static_cast<std::size_t>(a)] != type_b[static_cast<std::size_t>(b)])
      continue;
    const auto n = static_cast<double>(together);
    // Of each: a segment that wrongly holds two shapes in one tile joins at most the larger.
    if (together >= p.min_shared && n >= p.min_agreement * static_cast<double>(counts.in_a.at(a)) &&
        n >= p.min_agreement * static_cast<double>(counts.in_b.at(b)))
      joins.push_back(pair);
  }
  return joins;  // std::map iterates in ascending order
}

DisjointSets::DisjointSets(std::size_t n) : parent_(n) {
  std::iota(parent_.begin(), parent_.end(), std::size_t{0});
}

std::size_t DisjointSets::find(std::size_t x) {
  while (parent_[x] != x) {
    parent_[x] = parent_[parent_[x]];
    x = parent_[x];
  }
  return x;
}

void DisjointSets::join(std::size_t a, std::size_t b) {
  a = find(a);
  b = find(b);
  if (a == b)
    return;
  if (b < a)
    std::swap(a, b);
  parent_[b] = a;  // the smaller index represents the set
}

}  // namespace slipfit
