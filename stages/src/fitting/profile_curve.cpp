#include "slipfit/fitting/profile_curve.h"

#ifndef NANOFLANN_FIRST_MATCH
#define NANOFLANN_FIRST_MATCH  // equal distances: the lower index first, as NanoflannSearch
#endif
#include <nanoflann.hpp>

#include "slipfit/core/exceptions.h"
#include "slipfit/core/median.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <tuple>
#include <utility>

namespace slipfit {

std::size_t ProfileCurve::segmentCount() const {
  if (vertices.size() < 2)
    return 0;
  return closed ? vertices.size() : vertices.size() - 1;
}

namespace {

/// Squared distance from \a q to the segment a–b in the metric diag(s², 1), and the parameter of
/// the nearest point.
double segmentDistance2(const Eigen::Vector2d& q, const Eigen::Vector2d& a,
                        const Eigen::Vector2d& b, double s, double* t_out = nullptr) {
  const Eigen::Vector2d qa(s * (q.x() - a.x()), q.y() - a.y());
  const Eigen::Vector2d ba(s * (b.x() - a.x()), b.y() - a.y());
  const double len2 = ba.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp(qa.dot(ba) / len2, 0.0, 1.0) : 0.0;
  if (t_out)
    *t_out = t;
  return (qa - t * ba).squaredNorm();
}

/// The nearest segment of \a curve to \a q (Euclidean): its index, parameter and squared distance.
struct Nearest {
  std::size_t segment = 0;
  double t = 0.0;
  double d2 = std::numeric_limits<double>::infinity();
};

Nearest nearestSegment(const ProfileCurve& curve, const Eigen::Vector2d& q) {
  Nearest best;
  const std::size_t v = curve.vertices.size();
  for (std::size_t j = 0; j < curve.segmentCount(); ++j) {
    double t = 0.0;
    const double d2 = segmentDistance2(q, curve.vertices[j], curve.vertices[(j + 1) % v], 1.0, &t);
    if (d2 < best.d2)
      best = {j, t, d2};
  }
  return best;
}

/// One least-squares update of the vertices: each point at its nearest segment's parameter, plus
/// smoothing × the squared second differences (a curvature penalty) and a tiny ridge.
void refineVertices(const Eigen::Ref<const Eigen::Matrix2Xd>& q, ProfileCurve& curve,
                    double smoothing) {
  const auto v = static_cast<Eigen::Index>(curve.vertices.size());
  if (v < 2)
    return;
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixX2d rhs = Eigen::MatrixX2d::Zero(v, 2);
  for (Eigen::Index i = 0; i < q.cols(); ++i) {
    const Nearest n = nearestSegment(curve, q.col(i));
    const auto j = static_cast<Eigen::Index>(n.segment), k = (j + 1) % v;
    const double a = 1.0 - n.t, b = n.t;
    entries.emplace_back(j, j, a * a);
    entries.emplace_back(k, k, b * b);
    entries.emplace_back(j, k, a * b);
    entries.emplace_back(k, j, a * b);
    rhs.row(j) += a * q.col(i).transpose();
    rhs.row(k) += b * q.col(i).transpose();
  }
  const double per_vertex = static_cast<double>(q.cols()) / static_cast<double>(v);
  const double lambda = smoothing * per_vertex;
  const Eigen::Index first = curve.closed ? 0 : 1, last = curve.closed ? v : v - 1;
  if (v >= 3)
    for (Eigen::Index k = first; k < last; ++k) {
      const Eigen::Index idx[3] = {(k - 1 + v) % v, k, (k + 1) % v};
      const double c[3] = {1.0, -2.0, 1.0};
      for (int r = 0; r < 3; ++r)
        for (int s = 0; s < 3; ++s)
          entries.emplace_back(idx[r], idx[s], lambda * c[r] * c[s]);
    }
  // The ridge pulls a vertex no point projects onto toward where it is.
  const double ridge = 1e-6 * std::max(per_vertex, 1.0);
  for (Eigen::Index k = 0; k < v; ++k) {
    entries.emplace_back(k, k, ridge);
    rhs.row(k) += ridge * curve.vertices[static_cast<std::size_t>(k)].transpose();
  }
  Eigen::SparseMatrix<double> a(v, v);
  a.setFromTriplets(entries.begin(), entries.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(a);
  if (ldlt.info() != Eigen::Success)
    return;
  const Eigen::MatrixX2d x = ldlt.solve(rhs);
  if (!x.allFinite())
    return;
  for (Eigen::Index k = 0; k < v; ++k)
    curve.vertices[static_cast<std::size_t>(k)] = x.row(k).transpose();
}

/// Douglas–Peucker on vertices [from, to] of \a path (indices into it): the kept indices.
void douglasPeucker(const std::vector<Eigen::Vector2d>& path, std::size_t from, std::size_t to,
                    double tolerance, std::vector<char>& keep) {
  std::vector<std::pair<std::size_t, std::size_t>> stack{{from, to}};
  while (!stack.empty()) {
    const auto [a, b] = stack.back();
    stack.pop_back();
    if (b <= a + 1)
      continue;
    double worst = -1.0;
    std::size_t at = a;
    for (std::size_t k = a + 1; k < b; ++k) {
      const double d2 = segmentDistance2(path[k], path[a], path[b], 1.0);
      if (d2 > worst) {
        worst = d2;
        at = k;
      }
    }
    if (worst > tolerance * tolerance) {
      keep[at] = 1;
      stack.emplace_back(a, at);
      stack.emplace_back(at, b);
    }
  }
}

ProfileCurve simplify(const ProfileCurve& curve, double tolerance) {
  const std::vector<Eigen::Vector2d>& p = curve.vertices;
  const std::size_t v = p.size();
  if (v < 3)
    return curve;
  std::vector<char> keep(v, 0);
  ProfileCurve out;
  out.closed = curve.closed;
  if (!curve.closed) {
    keep.front() = keep.back() = 1;
    douglasPeucker(p, 0, v - 1, tolerance, keep);
  } else {
    // Split at vertex 0 and the vertex farthest from it; both halves simplified.
    std::size_t far = 0;
    for (std::size_t k = 1; k < v; ++k)
      if ((p[k] - p[0]).squaredNorm() > (p[far] - p[0]).squaredNorm())
        far = k;
    std::vector<Eigen::Vector2d> ring = p;
    ring.push_back(p[0]);
    std::vector<char> ring_keep(v + 1, 0);
    ring_keep[0] = ring_keep[far] = ring_keep[v] = 1;
    douglasPeucker(ring, 0, far, tolerance, ring_keep);
    douglasPeucker(ring, far, v, tolerance, ring_keep);
    std::copy(ring_keep.begin(), ring_keep.begin() + static_cast<std::ptrdiff_t>(v), keep.begin());
  }
  for (std::size_t k = 0; k < v; ++k)
    if (keep[k])
      out.vertices.push_back(p[k]);
  if (out.closed && out.vertices.size() < 3)
    return curve;
  return out;
}

/// \a curve's vertices placed every \a step of its length (the ends kept): the tree's nodes are
/// b to 2 b apart and can nearly coincide, which least squares folds.
ProfileCurve resample(const ProfileCurve& curve, double step) {
  std::vector<Eigen::Vector2d> path = curve.vertices;
  if (curve.closed)
    path.push_back(path.front());
  std::vector<double> along(path.size(), 0.0);
  for (std::size_t k = 1; k < path.size(); ++k)
    along[k] = along[k - 1] + (path[k] - path[k - 1]).norm();
  const double length = along.back();
  ProfileCurve out;
  out.closed = curve.closed;
  const auto pieces = static_cast<std::size_t>(std::max(1.0, std::round(length / step)));
  const std::size_t count = curve.closed ? pieces : pieces + 1;
  std::size_t k = 1;
  for (std::size_t j = 0; j < count; ++j) {
    const double at = length * static_cast<double>(j) / static_cast<double>(pieces);
    while (k + 1 < path.size() && along[k] < at)
      ++k;
    const double span = along[k] - along[k - 1];
    const double t = span > 0.0 ? std::clamp((at - along[k - 1]) / span, 0.0, 1.0) : 0.0;
    out.vertices.push_back((1.0 - t) * path[k - 1] + t * path[k]);
  }
  if (out.closed && out.vertices.size() < 3)
    return curve;
  return out;
}

/// Drops the vertices where the polyline turns back on itself (consecutive segments more than
/// 90° apart): folds least squares can leave where two vertices swap.
void unfold(ProfileCurve& curve) {
  for (bool changed = true; changed && curve.vertices.size() > 3;) {
    changed = false;
    const std::size_t v = curve.vertices.size();
    const std::size_t first = curve.closed ? 0 : 1, last = curve.closed ? v : v - 1;
    for (std::size_t k = first; k < last; ++k) {
      const Eigen::Vector2d& a = curve.vertices[(k + v - 1) % v];
      const Eigen::Vector2d& b = curve.vertices[k];
      const Eigen::Vector2d& c = curve.vertices[(k + 1) % v];
      if ((b - a).dot(c - b) < 0.0) {
        curve.vertices.erase(curve.vertices.begin() + static_cast<std::ptrdiff_t>(k));
        changed = true;
        break;
      }
    }
  }
}

/// Union–find for Kruskal's algorithm.
struct Components {
  std::vector<std::size_t> parent;
  explicit Components(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  std::size_t find(std::size_t i) {
    while (parent[i] != i)
      i = parent[i] = parent[parent[i]];
    return i;
  }
};

/// Cells of width b over 2D points, for the neighbour queries of orderedNodes.
class Grid {
 public:
  Grid(const std::vector<Eigen::Vector2d>& p, double b) : b_(b) {
    for (std::size_t i = 0; i < p.size(); ++i)
      cells_[key(p[i])].push_back(i);
  }
  /// Indices of the points within \a radius of \a c, ascending within each cell.
  template <class Visit>
  void near(const std::vector<Eigen::Vector2d>& p, const Eigen::Vector2d& c, double radius,
            Visit&& visit) const {
    const auto [x, y] = key(c);
    const auto reach = static_cast<long>(std::ceil(radius / b_));
    for (long dx = -reach; dx <= reach; ++dx)
      for (long dy = -reach; dy <= reach; ++dy) {
        const auto it = cells_.find({x + dx, y + dy});
        if (it == cells_.end())
          continue;
        for (std::size_t i : it->second)
          if ((p[i] - c).squaredNorm() <= radius * radius)
            visit(i);
      }
  }

 private:
  std::pair<long, long> key(const Eigen::Vector2d& q) const {
    return {static_cast<long>(std::floor(q.x() / b_)), static_cast<long>(std::floor(q.y() / b_))};
  }
  double b_;
  std::map<std::pair<long, long>, std::vector<std::size_t>> cells_;
};

/// The ordered path of nodes along the points (steps 1–2 of fitProfileCurve).
ProfileCurve orderedNodes(const Eigen::Matrix2Xd& q, double b) {
  std::vector<Eigen::Vector2d> p(static_cast<std::size_t>(q.cols()));
  for (Eigen::Index i = 0; i < q.cols(); ++i)
    p[static_cast<std::size_t>(i)] = q.col(i);
  const Grid grid(p, b);
  // A cover: each point not yet within b of a node starts one; the node sits at the centroid of
  // the points within b of it (across a noisy curve of thickness below b, one node, not two).
  std::vector<char> covered(p.size(), 0);
  std::vector<Eigen::Vector2d> nodes;
  std::vector<int> counts;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (covered[i])
      continue;
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    int count = 0;
    grid.near(p, p[i], b, [&](std::size_t j) {
      covered[j] = 1;
      sum += p[j];
      ++count;
    });
    nodes.push_back(sum / count);
    counts.push_back(count);
  }
  const std::size_t m = nodes.size();
  const Grid node_grid(nodes, b);
  std::vector<std::tuple<double, std::size_t, std::size_t>> edges;
  for (std::size_t k = 0; k < m; ++k)
    node_grid.near(nodes, nodes[k], 3.0 * b, [&](std::size_t j) {
      if (j > k)
        edges.emplace_back((nodes[k] - nodes[j]).norm(), k, j);
    });
  std::sort(edges.begin(), edges.end());
  Components components(m);
  std::vector<std::vector<std::pair<std::size_t, double>>> tree(m);
  for (const auto& [length, i, j] : edges) {
    const std::size_t a = components.find(i), c = components.find(j);
    if (a == c)
      continue;
    components.parent[a] = c;
    tree[i].emplace_back(j, length);
    tree[j].emplace_back(i, length);
  }
  // The component holding most points.
  std::vector<int> held(m, 0);
  for (std::size_t k = 0; k < m; ++k)
    held[components.find(k)] += counts[k];
  const std::size_t root =
      static_cast<std::size_t>(std::max_element(held.begin(), held.end()) - held.begin());
  std::size_t start = 0;
  while (components.find(start) != root)
    ++start;
  // Farthest node (along the tree) from a node, with the predecessors of the walk.
  auto farthest = [&](std::size_t from, std::vector<std::size_t>& previous) {
    std::vector<double> reach(m, -1.0);
    previous.assign(m, m);
    std::vector<std::size_t> stack{from};
    reach[from] = 0.0;
    std::size_t best = from;
    while (!stack.empty()) {
      const std::size_t k = stack.back();
      stack.pop_back();
      if (reach[k] > reach[best])
        best = k;
      for (const auto& [j, length] : tree[k])
        if (reach[j] < 0.0) {
          reach[j] = reach[k] + length;
          previous[j] = k;
          stack.push_back(j);
        }
    }
    return std::make_pair(best, reach[best]);
  };
  std::vector<std::size_t> previous;
  const std::size_t a = farthest(start, previous).first;
  const auto [z, length] = farthest(a, previous);
  ProfileCurve curve;
  for (std::size_t k = z; k != m; k = previous[k])
    curve.vertices.push_back(nodes[k]);
  curve.closed =
      curve.vertices.size() >= 4 && length >= 8.0 * b && (nodes[a] - nodes[z]).norm() <= 4.0 * b;
  return curve;
}

/// The second-difference penalty of the vertices' least squares, per point a vertex holds.
constexpr double kSmoothing = 0.01;

}  // namespace

void refineProfileCurve(const Eigen::Ref<const Eigen::Matrix2Xd>& q, ProfileCurve& curve) {
  refineVertices(q, curve, kSmoothing);
  unfold(curve);
}

ProfileProjection projectOnProfile(const ProfileCurve& curve, const Eigen::Vector2d& q,
                                   double first_scale, double period) {
  ProfileProjection best;
  best.distance = std::numeric_limits<double>::infinity();
  const std::size_t v = curve.vertices.size();
  if (v == 0)
    return best;
  double best2 = std::numeric_limits<double>::infinity();
  Eigen::Vector2d best_offset = Eigen::Vector2d::Zero();
  const int images = period > 0.0 ? 1 : 0;
  const std::size_t segments = std::max<std::size_t>(1, curve.segmentCount());
  for (int image = -images; image <= images; ++image) {
    const Eigen::Vector2d p(q.x() + image * period, q.y());
    for (std::size_t j = 0; j < segments; ++j) {
      const Eigen::Vector2d& a = curve.vertices[j];
      const Eigen::Vector2d& b = curve.vertices[v == 1 ? 0 : (j + 1) % v];
      double t = 0.0;
      const double d2 = segmentDistance2(p, a, b, first_scale, &t);
      if (d2 < best2) {
        best2 = d2;
        best.segment = j;
        best.t = t;
        const Eigen::Vector2d at = (1.0 - t) * a + t * b;
        best_offset = Eigen::Vector2d(first_scale * (p.x() - at.x()), p.y() - at.y());
      }
    }
  }
  best.distance = std::sqrt(best2);
  if (best.distance > 0.0)
    best.unit = best_offset / best.distance;
  return best;
}

struct ProfileIndex::Best {
  double d2 = std::numeric_limits<double>::infinity();
  int image = 0;
  std::size_t segment = 0;
  double t = 0.0;
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();
};

ProfileIndex::ProfileIndex(const ProfileCurve& curve, double period)
    : curve_(&curve), period_(period) {
  const std::size_t v = curve.vertices.size();
  if (v < 2)
    return;
  Eigen::Vector2d lo = curve.vertices.front(), hi = lo;
  for (const Eigen::Vector2d& x : curve.vertices) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  const std::size_t count = curve.segmentCount();
  double length = 0.0;
  for (std::size_t j = 0; j < count; ++j)
    length += (curve.vertices[(j + 1) % v] - curve.vertices[j]).norm();
  const double extent = (hi - lo).maxCoeff();
  cell_ = std::max({length / static_cast<double>(count), extent / 128.0, 1e-300});
  origin_ = lo;
  nx_ = static_cast<int>(std::floor((hi.x() - lo.x()) / cell_)) + 1;
  ny_ = static_cast<int>(std::floor((hi.y() - lo.y()) / cell_)) + 1;
  const auto cellOf = [&](const Eigen::Vector2d& x) {
    return Eigen::Vector2i(
        std::clamp(static_cast<int>(std::floor((x.x() - origin_.x()) / cell_)), 0, nx_ - 1),
        std::clamp(static_cast<int>(std::floor((x.y() - origin_.y()) / cell_)), 0, ny_ - 1));
  };
  // Two passes over the segments' cell boxes: the counts, then the lists.
  offsets_.assign(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_) + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<std::size_t> fill;
    if (pass == 1) {
      for (std::size_t c = 1; c < offsets_.size(); ++c)
        offsets_[c] += offsets_[c - 1];
      segments_.resize(offsets_.back());
      fill.assign(offsets_.begin(), offsets_.end() - 1);
    }
    for (std::size_t j = 0; j < count; ++j) {
      const Eigen::Vector2d& a = curve.vertices[j];
      const Eigen::Vector2d& b = curve.vertices[(j + 1) % v];
      const Eigen::Vector2i c0 = cellOf(a.cwiseMin(b)), c1 = cellOf(a.cwiseMax(b));
      for (int iy = c0.y(); iy <= c1.y(); ++iy)
        for (int ix = c0.x(); ix <= c1.x(); ++ix) {
          const std::size_t c = static_cast<std::size_t>(iy) * static_cast<std::size_t>(nx_) +
                                static_cast<std::size_t>(ix);
          if (pass == 0)
            ++offsets_[c + 1];
          else
            segments_[fill[c]++] = j;
        }
    }
  }
}

void ProfileIndex::search(const Eigen::Vector2d& p, double s, int image, Best& best) const {
  const std::size_t v = curve_->vertices.size();
  // Segment j against the best so far (ties: the lower image, then the lower segment).
  const auto consider = [&](std::size_t j) {
    const Eigen::Vector2d& a = curve_->vertices[j];
    const Eigen::Vector2d& b = curve_->vertices[(j + 1) % v];
    double t = 0.0;
    const double d2 = segmentDistance2(p, a, b, s, &t);
    if (d2 < best.d2 ||
        (d2 == best.d2 && (image < best.image || (image == best.image && j < best.segment)))) {
      const Eigen::Vector2d at = (1.0 - t) * a + t * b;
      best = {d2, image, j, t, Eigen::Vector2d(s * (p.x() - at.x()), p.y() - at.y())};
    }
  };
  // The grid's box: nothing in it is nearer than s times the distance to it (s ≤ 1). A query
  // further than kRings cells from it scans every segment: rings would be mostly empty.
  constexpr int kRings = 6;
  const Eigen::Vector2d far_corner = origin_ + cell_ * Eigen::Vector2d(nx_, ny_);
  const double to_box = (p - p.cwiseMax(origin_).cwiseMin(far_corner)).norm();
  if (s * to_box * s * to_box > best.d2)
    return;
  if (to_box > kRings * cell_) {
    for (std::size_t j = 0; j < curve_->segmentCount(); ++j)
      consider(j);
    return;
  }
  const int cx =
      std::clamp(static_cast<int>(std::floor((p.x() - origin_.x()) / cell_)), 0, nx_ - 1);
  const int cy =
      std::clamp(static_cast<int>(std::floor((p.y() - origin_.y()) / cell_)), 0, ny_ - 1);
  const auto visit = [&](int ix, int iy) {
    const std::size_t c =
        static_cast<std::size_t>(iy) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(ix);
    for (std::size_t k = offsets_[c]; k < offsets_[c + 1]; ++k)
      consider(segments_[k]);
  };
  // Ring r holds the cells r steps from the query's (clamped) cell; none of them is nearer than
  // s (r − 1) cells: the query's projection onto the box lies in its cell. Still open after
  // kRings rings (a small scale), the rest is scanned whole.
  const int rings = std::max(nx_, ny_);
  for (int r = 0; r <= rings; ++r) {
    if (r >= 1) {
      const double bound = s * (r - 1) * cell_;
      if (bound * bound > best.d2)
        return;
    }
    if (r > kRings) {
      for (std::size_t j = 0; j < curve_->segmentCount(); ++j)
        consider(j);
      return;
    }
    for (int iy = cy - r; iy <= cy + r; ++iy) {
      if (iy < 0 || iy >= ny_)
        continue;
      const bool edge = iy == cy - r || iy == cy + r;
      for (int ix = cx - r; ix <= cx + r; ix += (edge || r == 0) ? 1 : 2 * r)
        if (ix >= 0 && ix < nx_)
          visit(ix, iy);
    }
  }
}

ProfileProjection ProfileIndex::project(const Eigen::Vector2d& q, double first_scale) const {
  if (offsets_.empty())
    return projectOnProfile(*curve_, q, first_scale, period_);
  Best best;
  best.image = 2;
  // The query itself first: its images a period away are nearer only at the strip's ends.
  search(q, first_scale, 0, best);
  if (period_ > 0.0)
    for (const int image : {-1, 1})
      search(Eigen::Vector2d(q.x() + image * period_, q.y()), first_scale, image, best);
  ProfileProjection out;
  out.segment = best.segment;
  out.t = best.t;
  out.distance = std::sqrt(best.d2);
  if (out.distance > 0.0)
    out.unit = best.offset / out.distance;
  return out;
}

double profileDistance(const ProfileCurve& curve, const Eigen::Vector2d& q, double first_scale,
                       double period) {
  return projectOnProfile(curve, q, first_scale, period).distance;
}

namespace {

/// nanoflann's view of 2D points.
struct PlanePoints {
  const Eigen::Matrix2Xd* q;
  std::size_t kdtree_get_point_count() const { return static_cast<std::size_t>(q->cols()); }
  double kdtree_get_pt(std::size_t i, std::size_t d) const {
    return (*q)(static_cast<Eigen::Index>(d), static_cast<Eigen::Index>(i));
  }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

}  // namespace

double estimateProfileNoise(const Eigen::Ref<const Eigen::Matrix2Xd>& q_in, double guess) {
  if (!(guess > 0.0) || !std::isfinite(guess))
    throw InvalidParameterError("estimateProfileNoise: the guess " + std::to_string(guess) +
                                " is not positive and finite");
  constexpr std::size_t kMost = 256, kLeast = 8;
  const Eigen::Matrix2Xd q = q_in;
  if (q.cols() < static_cast<Eigen::Index>(kLeast) || !q.allFinite())
    return 0.0;
  const PlanePoints adaptor{&q};
  using Tree =
      nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PlanePoints>,
                                          PlanePoints, 2, std::size_t>;
  Tree tree(2, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  tree.buildIndex();
  const auto n = static_cast<std::size_t>(q.cols());
  const std::size_t stride = std::max<std::size_t>(1, (n + 1999) / 2000);
  const std::size_t k = std::min(kMost, n);
  std::vector<std::size_t> index(k);
  std::vector<double> d2(k), variances;
  // One estimate over neighbourhoods of radius R.
  const auto estimate = [&](double radius) {
    variances.clear();
    for (std::size_t i = 0; i < n; i += stride) {
      const double query[2] = {q(0, static_cast<Eigen::Index>(i)),
                               q(1, static_cast<Eigen::Index>(i))};
      const std::size_t found = tree.knnSearch(query, k, index.data(), d2.data());
      std::size_t m = 0;
      while (m < found && d2[m] <= radius * radius)
        ++m;
      m = std::max(m, std::min(kLeast, found));
      if (m < kLeast)
        continue;
      Eigen::Vector2d c = Eigen::Vector2d::Zero();
      for (std::size_t j = 0; j < m; ++j)
        c += q.col(static_cast<Eigen::Index>(index[j]));
      c /= static_cast<double>(m);
      Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
      for (std::size_t j = 0; j < m; ++j) {
        const Eigen::Vector2d d = q.col(static_cast<Eigen::Index>(index[j])) - c;
        cov += d * d.transpose();
      }
      // The principal direction: the eigenvector of the larger eigenvalue of the 2 × 2 matrix.
      const double tr = cov.trace(), det = cov.determinant();
      const double larger = 0.5 * tr + std::sqrt(std::max(0.0, 0.25 * tr * tr - det));
      Eigen::Vector2d u(cov(0, 1), larger - cov(0, 0));
      if (u.squaredNorm() <= 1e-300)
        u = cov(0, 0) >= cov(1, 1) ? Eigen::Vector2d::UnitX() : Eigen::Vector2d::UnitY();
      u.normalize();
      const Eigen::Vector2d v(-u.y(), u.x());
      Eigen::MatrixX3d a(static_cast<Eigen::Index>(m), 3);
      Eigen::VectorXd b(static_cast<Eigen::Index>(m));
      for (std::size_t j = 0; j < m; ++j) {
        const Eigen::Vector2d d = q.col(static_cast<Eigen::Index>(index[j])) - c;
        const double s = d.dot(u);
        a.row(static_cast<Eigen::Index>(j)) << 1.0, s, s * s;
        b[static_cast<Eigen::Index>(j)] = d.dot(v);
      }
      const Eigen::Vector3d x = a.colPivHouseholderQr().solve(b);
      const double nu = static_cast<double>(m - 3);
      // The median of χ²_ν / ν, Wilson–Hilferty: (1 − 2 / (9 ν))³.
      variances.push_back((a * x - b).squaredNorm() / nu / std::pow(1.0 - 2.0 / (9.0 * nu), 3));
    }
    return variances.empty() ? 0.0 : std::sqrt(medianInPlace(variances));
  };
  double sigma = guess;
  for (int round = 0; round < 4; ++round) {
    const double next = estimate(8.0 * sigma);
    if (!(next > 0.0))
      return round == 0 ? 0.0 : sigma;
    const bool settled = next > 0.9 * sigma;
    sigma = std::min(sigma, next);
    if (settled)
      break;
  }
  return sigma;
}

ProfileFit fitProfileCurve(const Eigen::Ref<const Eigen::Matrix2Xd>& q_in, double noise) {
  ProfileFit out;
  std::vector<Eigen::Index> finite;
  for (Eigen::Index i = 0; i < q_in.cols(); ++i)
    if (q_in.col(i).allFinite())
      finite.push_back(i);
  if (finite.size() < 10) {
    out.reason = "profile fit: fewer than 10 finite points";
    return out;
  }
  Eigen::Matrix2Xd q(2, static_cast<Eigen::Index>(finite.size()));
  for (std::size_t k = 0; k < finite.size(); ++k)
    q.col(static_cast<Eigen::Index>(k)) = q_in.col(finite[k]);
  const double diagonal = (q.rowwise().maxCoeff() - q.rowwise().minCoeff()).norm();
  if (!(diagonal > 0.0)) {
    out.reason = "profile fit: the points are on one spot";
    return out;
  }
  const double n = static_cast<double>(q.cols());
  const double sigma = std::max(0.0, noise);
  const double b = std::max({4.0 * sigma, 16.0 * diagonal / n, diagonal / 400.0});
  ProfileCurve curve = orderedNodes(q, b);
  if (curve.vertices.size() < 2) {
    out.reason = "profile fit: the points do not spread along a curve";
    return out;
  }
  curve = resample(curve, b);
  for (int pass = 0; pass < 2; ++pass) {
    refineVertices(q, curve, kSmoothing);
    unfold(curve);
  }
  curve = simplify(curve, sigma > 0.0 ? sigma : b / 50.0);
  for (int pass = 0; pass < 3; ++pass) {
    refineVertices(q, curve, kSmoothing);
    unfold(curve);
  }
  double sum = 0.0;
  for (Eigen::Index i = 0; i < q.cols(); ++i) {
    const double d = profileDistance(curve, q.col(i));
    sum += d * d;
  }
  out.curve = std::move(curve);
  out.rms_distance = std::sqrt(sum / n);
  out.ok = std::isfinite(out.rms_distance);
  if (!out.ok)
    out.reason = "profile fit: the distances overflowed";
  return out;
}

}  // namespace slipfit
