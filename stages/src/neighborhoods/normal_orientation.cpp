#include "slipfit/neighborhoods/normal_orientation.h"

#include "slipfit/core/exceptions.h"

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <queue>
#include <tuple>
#include <vector>

namespace slipfit {

namespace {

bool finiteColumn(const ConstCoords3Map& m, Eigen::Index i) {
  return m.col(i).allFinite();
}

/// Symmetric adjacency (CSR) of the neighbor graph restricted to vertices with finite normals.
struct Adjacency {
  std::vector<std::uint64_t> offsets;
  std::vector<std::uint32_t> targets;
};

Adjacency symmetrise(const Neighborhoods& graph, const std::vector<char>& valid) {
  const std::size_t n = graph.size();
  Adjacency adj;
  std::vector<std::uint32_t> degree(n, 0);
  auto for_each_edge = [&](const std::function<void(std::size_t, std::size_t)>& f) {
    for (std::size_t i = 0; i < n; ++i) {
      if (!valid[i])
        continue;
      for (const auto j : graph[i])
        if (static_cast<std::size_t>(j) != i && valid[static_cast<std::size_t>(j)])
          f(i, static_cast<std::size_t>(j));
    }
  };
  for_each_edge([&](std::size_t i, std::size_t j) {
    ++degree[i];
    ++degree[j];
  });
  adj.offsets.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
    adj.offsets[i + 1] = adj.offsets[i] + degree[i];
  adj.targets.resize(adj.offsets[n]);
  std::vector<std::uint64_t> fill(adj.offsets.begin(), adj.offsets.end() - 1);
  for_each_edge([&](std::size_t i, std::size_t j) {
    adj.targets[fill[i]++] = static_cast<std::uint32_t>(j);
    adj.targets[fill[j]++] = static_cast<std::uint32_t>(i);
  });
  return adj;
}

}  // namespace

std::size_t orientTowardsViewpoint(const ConstCoords3Map& points, Coords3Map normals,
                                   const Eigen::Vector3f& viewpoint) {
  std::size_t flipped = 0;
  for (Eigen::Index i = 0; i < normals.cols(); ++i) {
    if ((viewpoint - points.col(i)).dot(normals.col(i)) < 0.0f) {
      normals.col(i) = -normals.col(i);
      ++flipped;
    }
  }
  return flipped;
}

std::size_t orientLikeReference(Coords3Map normals, const ConstCoords3Map& reference) {
  if (reference.cols() != normals.cols())
    throw InvalidParameterError("orientLikeReference: " + std::to_string(reference.cols()) +
                                " reference normals for " + std::to_string(normals.cols()) +
                                " normals");
  std::size_t flipped = 0;
  for (Eigen::Index i = 0; i < normals.cols(); ++i) {
    if (normals.col(i).dot(reference.col(i)) < 0.0f) {
      normals.col(i) = -normals.col(i);
      ++flipped;
    }
  }
  return flipped;
}

ConsistentOrientationReport orientConsistently(const ConstCoords3Map& points, Coords3Map normals,
                                               const Neighborhoods& graph,
                                               const std::optional<Eigen::Vector3f>& viewpoint) {
  const auto n = static_cast<std::size_t>(normals.cols());
  if (points.cols() != normals.cols() || graph.size() != n)
    throw InvalidParameterError("orientConsistently: points, normals and graph differ in size");
  const ConstCoords3Map normals_view(normals.data(), 3, normals.cols(), normals.outerStride());

  std::vector<char> valid(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    valid[i] = finiteColumn(normals_view, i) && finiteColumn(points, i) ? 1 : 0;
  const Adjacency adj = symmetrise(graph, valid);

  ConsistentOrientationReport report;
  std::vector<char> done(n, 0);
  std::vector<std::uint32_t> component;
  // (cost, target, source): ties broken by index keep the result deterministic.
  using Edge = std::tuple<float, std::uint32_t, std::uint32_t>;
  std::priority_queue<Edge, std::vector<Edge>, std::greater<Edge>> heap;

  auto flip_if_needed = [&](std::size_t from, std::size_t to) {
    if (normals.col(from).dot(normals.col(to)) < 0.0f) {
      normals.col(to) = -normals.col(to);
      ++report.flipped;
    }
  };

  std::vector<char> seen(n, 0);
  for (std::size_t start = 0; start < n; ++start) {
    if (!valid[start] || seen[start])
      continue;
    // Collect the component (breadth first) to choose its seed.
    component.assign(1, static_cast<std::uint32_t>(start));
    seen[start] = 1;
    for (std::size_t head = 0; head < component.size(); ++head) {
      const std::size_t u = component[head];
      for (auto e = adj.offsets[u]; e < adj.offsets[u + 1]; ++e) {
        const std::uint32_t v = adj.targets[e];
        if (!seen[v]) {
          seen[v] = 1;
          component.push_back(v);
        }
      }
    }
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const auto i : component)
      centroid += points.col(i).cast<double>();
    centroid /= static_cast<double>(component.size());
    // Seed: the point where the orientation cue is strongest. With a viewpoint, the normal most
    // nearly along the line of sight, |cos(n, v − p)| / ‖v − p‖ (nearer points win, so a closed
    // surface's far side never seeds), oriented towards the viewer; without, the normal most
    // nearly radial from the centroid, |(p − c)·n|, oriented away from it (outward when closed).
    std::size_t seed = component.front();
    double best = -std::numeric_limits<double>::infinity();
    for (const auto i : component) {
      const Eigen::Vector3d p = points.col(i).cast<double>();
      const Eigen::Vector3d n = normals.col(i).cast<double>();
      double score = 0.0;
      if (viewpoint) {
        const Eigen::Vector3d sight = viewpoint->cast<double>() - p;
        const double d2 = sight.squaredNorm();
        score = d2 > 0.0 ? std::abs(n.dot(sight)) / d2 : 0.0;
      } else {
        score = std::abs((p - centroid).dot(n));
      }
      if (score > best) {
        best = score;
        seed = i;
      }
    }
    const Eigen::Vector3f outward =
        viewpoint ? Eigen::Vector3f(*viewpoint - points.col(seed))
                  : Eigen::Vector3f(points.col(seed) - centroid.cast<float>());
    if (normals.col(seed).dot(outward) < 0.0f) {
      normals.col(seed) = -normals.col(seed);
      ++report.flipped;
    }
    ++report.components;

    // Prim's algorithm from the seed, lazily deleting stale heap entries.
    auto push_edges = [&](std::size_t u) {
      for (auto e = adj.offsets[u]; e < adj.offsets[u + 1]; ++e) {
        const std::uint32_t v = adj.targets[e];
        if (done[v])
          continue;
        const float cost = 1.0f - std::abs(normals.col(u).dot(normals.col(v)));
        heap.emplace(cost, v, static_cast<std::uint32_t>(u));
      }
    };
    done[seed] = 1;
    ++report.oriented;
    push_edges(seed);
    while (!heap.empty()) {
      const std::uint32_t v = std::get<1>(heap.top());
      const std::uint32_t u = std::get<2>(heap.top());
      heap.pop();
      if (done[v])
        continue;
      flip_if_needed(u, v);
      done[v] = 1;
      ++report.oriented;
      push_edges(v);
    }
  }
  return report;
}

}  // namespace slipfit
