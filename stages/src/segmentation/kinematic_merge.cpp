#include "slipfit/segmentation/kinematic_merge.h"

#include "slipfit/core/angle_units.h"
#include "slipfit/fitting/weighted_fit.h"
#include "slipfit/slippage/shape_classification.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <utility>
#include <vector>

namespace slipfit {

namespace {

/// Two axes within this angle are one (the axes of pieces of a turned part, fitted on a band
/// each, scatter by a degree or two at the noise of a scan).
constexpr double kAxisAngle = 5.0 * kDegree;
/// Segments touching at fewer neighbour pairs than this are not adjacent.
constexpr std::size_t kMinContacts = 3;
/// Points classified per group at most (every ⌈n / kGroupPoints⌉-th).
constexpr std::size_t kGroupPoints = 30000;

/// What a segment's primitive says of a motion it could share.
struct MotionHint {
  enum Kind { none, line, centre, direction } kind = none;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  ///< line, direction (a plane: its normal)
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< line, centre
};

MotionHint hintOf(const Primitive& p) {
  MotionHint h;
  if (const auto* c = std::get_if<Cylinder>(&p))
    h = {MotionHint::line, c->axis.normalized(), c->point};
  else if (const auto* k = std::get_if<Cone>(&p))
    h = {MotionHint::line, k->axis.normalized(), k->apex};
  else if (const auto* t = std::get_if<Torus>(&p))
    h = {MotionHint::line, t->axis.normalized(), t->center};
  else if (const auto* s = std::get_if<Sphere>(&p))
    h = {MotionHint::centre, Eigen::Vector3d::UnitZ(), s->center};
  else if (const auto* q = std::get_if<Plane>(&p))
    h = {MotionHint::direction, q->normal.normalized(), Eigen::Vector3d::Zero()};
  return h;
}

double offLine(const Eigen::Vector3d& q, const Eigen::Vector3d& point,
               const Eigen::Vector3d& axis) {
  const Eigen::Vector3d w = q - point;
  return (w - w.dot(axis) * axis).norm();
}

bool parallel(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::abs(a.dot(b)) >= std::cos(kAxisAngle);
}

/// Whether two adjacent segments' primitives could be pieces of one kinematic surface: one axis
/// line (within kAxisAngle and \a reach), a sphere centred on the other's line, parallel
/// cylinders (an extrusion's strips) or a plane along a cylinder's axis.
bool sameMotion(const MotionHint& a, const MotionHint& b, double reach) {
  using K = MotionHint::Kind;
  if (a.kind == K::line && b.kind == K::line)
    return parallel(a.axis, b.axis);  // collinear (revolution, helix) or parallel (extrusion)
  if (a.kind == K::line && b.kind == K::centre)
    return offLine(b.point, a.point, a.axis) <= reach;
  if (a.kind == K::centre && b.kind == K::line)
    return sameMotion(b, a, reach);
  // A plane along a line's direction may be a flat strip of an extrusion (mergeKinematicSurfaces
  // attaches it only to a group larger than itself).
  if (a.kind == K::line && b.kind == K::direction)
    return std::abs(a.axis.dot(b.axis)) <= std::sin(kAxisAngle);
  if (a.kind == K::direction && b.kind == K::line)
    return sameMotion(b, a, reach);
  return false;
}

struct UnionFind {
  std::vector<std::size_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  std::size_t find(std::size_t i) {
    while (parent[i] != i)
      i = parent[i] = parent[parent[i]];
    return i;
  }
  void join(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b)
      parent[std::max(a, b)] = std::min(a, b);
  }
};

/// The segments' adjacency: pairs (a < b) with at least kMinContacts neighbour pairs across.
std::vector<std::pair<std::size_t, std::size_t>> adjacentPairs(
    const Neighborhoods& neighborhoods, const std::vector<std::int32_t>& labels) {
  std::map<std::pair<std::size_t, std::size_t>, std::size_t> contacts;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (labels[i] < 0)
      continue;
    for (const pcl::index_t j : neighborhoods[i]) {
      const std::int32_t other = labels[static_cast<std::size_t>(j)];
      if (other > labels[i])
        ++contacts[{static_cast<std::size_t>(labels[i]), static_cast<std::size_t>(other)}];
    }
  }
  std::vector<std::pair<std::size_t, std::size_t>> out;
  for (const auto& [pair, count] : contacts)
    if (count >= kMinContacts)
      out.push_back(pair);
  return out;
}

/// The kinematic surface of the group's points, when the whole-cloud classification answers one.
std::optional<KinematicFit> classifyGroup(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                          const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                                          const std::vector<int>& members) {
  const std::size_t stride = (members.size() + kGroupPoints - 1) / kGroupPoints;
  const auto m = static_cast<Eigen::Index>((members.size() + stride - 1) / stride);
  Eigen::Matrix3Xd x(3, m), n(3, m);
  for (Eigen::Index k = 0; k < m; ++k) {
    const int i = members[static_cast<std::size_t>(k) * stride];
    x.col(k) = points.col(i);
    n.col(k) = normals.col(i);
  }
  ShapeClassification c = classifyShape(x, n, Eigen::VectorXd::Ones(m));
  if (!c.kinematic_verdict || !c.kinematic_explains || !c.kinematic)
    return std::nullopt;
  return std::move(c.kinematic);
}

/// The members of \a group but the caps of a surface of revolution or a helix \a fit: segments a
/// plane across the axis (its normal within kAxisAngle of it) explains as well as their own
/// primitive does (RMS at most 1.5 × theirs or the noise). A flat end is a surface of revolution
/// too, and the classification of the group then takes it; it is a plane.
std::vector<std::size_t> withoutCaps(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                     const SegmentationResult& result,
                                     const std::vector<std::size_t>& group,
                                     const KinematicFit& fit) {
  if (fit.surface.type == KinematicType::extrusion)
    return group;
  std::vector<std::size_t> kept;
  for (const std::size_t k : group) {
    const Segment& s = result.segments[k];
    const Eigen::Matrix3Xd x = points(Eigen::all, s.indices);
    const FitResult plane = fitPrimitive(PrimitiveType::plane, x, Eigen::Matrix3Xd(3, 0),
                                         Eigen::VectorXd::Ones(x.cols()));
    const auto* p = std::get_if<Plane>(&plane.refined);
    const bool cap =
        plane.ok() && p &&
        std::abs(p->normal.normalized().dot(fit.surface.axis)) >= std::cos(kAxisAngle) &&
        plane.rms_distance <= 1.5 * std::max(s.rms_distance, result.noise);
    if (!cap)
      kept.push_back(k);
  }
  return kept;
}

/// Adds to \a segment the unassigned points next to it that its kinematic surface explains, from
/// the points of \a frontier outwards, until none is left.
void absorbExplained(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                     const Neighborhoods& neighborhoods, const SegmentationResult& result,
                     std::vector<std::int32_t>& labels, std::int32_t label, Segment& segment,
                     std::vector<int> frontier) {
  const KinematicProjector surface(segment.kinematic->surface);
  while (!frontier.empty()) {
    std::vector<int> next;
    for (const int i : frontier)
      for (const pcl::index_t j : neighborhoods[static_cast<std::size_t>(i)]) {
        const auto u = static_cast<std::size_t>(j);
        if (labels[u] != -1)
          continue;
        const Eigen::Vector3d p = points.col(j);
        if (surface.distance(p) <= result.tolerance(p)) {
          labels[u] = label;
          next.push_back(static_cast<int>(j));
        }
      }
    segment.indices.insert(segment.indices.end(), next.begin(), next.end());
    frontier = std::move(next);
  }
  std::sort(segment.indices.begin(), segment.indices.end());
}

/// Whether kinematic segment \a k explains fragment \a f as well as its own primitive does: 90 %
/// of its points within their tolerance of the surface, at an RMS distance at most the merge
/// factor (1.5) over the fragment's own (or the noise, when that is lower).
bool explainsFragment(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                      const SegmentationResult& result, const Segment& k, const Segment& f) {
  const KinematicProjector surface(k.kinematic->surface);
  const double n = static_cast<double>(f.indices.size());
  std::size_t beyond = 0;
  double sum = 0.0;
  for (const int i : f.indices) {
    const Eigen::Vector3d p = points.col(i);
    const double d = surface.distance(p);
    beyond += d <= result.tolerance(p) ? 0 : 1;
    if (beyond > 0.1 * n)
      return false;  // a plate next to a turned part is over after a few of its points
    sum += d * d;
  }
  const std::size_t within = f.indices.size() - beyond;
  return within >= 0.9 * n && std::sqrt(sum / n) <= 1.5 * std::max(f.rms_distance, result.noise);
}

/// Whether segment \a f could be a stretch of \a surface that its profile does not reach: a
/// kinematic segment of the same class on a parallel axis, or a cylinder, cone or torus whose
/// axis is the surface's (within kAxisAngle and \a reach), or a sphere centred on it. Extrusions
/// take no primitive this way (parallel cylinders are not pieces of one section).
bool sharesAxis(const KinematicSurface& surface, const Segment& f, double reach) {
  if (f.kinematic)
    return f.kinematic->surface.type == surface.type &&
           parallel(f.kinematic->surface.axis, surface.axis);
  if (surface.type == KinematicType::extrusion)
    return false;
  const MotionHint h = hintOf(f.fit.refined);
  if (h.kind == MotionHint::line)
    return parallel(h.axis, surface.axis) && offLine(h.point, surface.point, surface.axis) <= reach;
  if (h.kind == MotionHint::centre)
    return offLine(h.point, surface.point, surface.axis) <= reach;
  return false;
}

/// Gives each kinematic segment the adjacent segments it explains as well as they explain
/// themselves (a thread's rings that did not share an axis closely enough to be grouped, the
/// flank a plane took, a smaller kinematic segment of the same surface), then the unassigned points
/// next to those, until none is left. The fragments given away are left empty.
void absorbFragments(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                     const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                     const Neighborhoods& neighborhoods, const SegmentationResult& result,
                     std::vector<std::int32_t>& labels, std::vector<Segment>& all) {
  // A surface keeps explaining what it explained, and keeps failing what it failed: each pair is
  // judged once.
  std::set<std::pair<std::size_t, std::size_t>> judged;
  bool changed = true;
  while (changed) {
    changed = false;
    for (const auto& [a, b] : adjacentPairs(neighborhoods, labels)) {
      if (!judged.insert({a, b}).second)
        continue;
      const bool ka = all[a].kinematic.has_value(), kb = all[b].kinematic.has_value();
      if ((!ka && !kb) || all[a].indices.empty() || all[b].indices.empty())
        continue;
      // Two kinematic segments (a thread grouped in two stretches): the larger takes the other.
      const bool a_takes = ka && (!kb || all[a].indices.size() >= all[b].indices.size());
      const std::size_t k = a_takes ? a : b, f = a_takes ? b : a;
      std::optional<KinematicFit> joint;
      if (!explainsFragment(points, result, all[k], all[f])) {
        // Two stretches of one surface of the same class on one axis, each with a profile of
        // its own heights (a turned part grouped in two): one surface for both, if one explains
        // them.
        // So for a primitive piece on the axis at heights the profile does not reach (a band of
        // a turned part that its own group did not take).
        const KinematicSurface& surface = all[k].kinematic->surface;
        if (!sharesAxis(surface, all[f], 10.0 * result.distance))
          continue;
        std::vector<int> both = all[k].indices;
        both.insert(both.end(), all[f].indices.begin(), all[f].indices.end());
        std::sort(both.begin(), both.end());
        joint = classifyGroup(points, normals, both);
        if (!joint || joint->surface.type != all[k].kinematic->surface.type)
          continue;
      }
      for (const int i : all[f].indices)
        labels[static_cast<std::size_t>(i)] = static_cast<std::int32_t>(k);
      all[k].indices.insert(all[k].indices.end(), all[f].indices.begin(), all[f].indices.end());
      std::vector<int> taken = std::move(all[f].indices);
      all[f].indices.clear();
      if (joint) {
        // A new surface: what it explains is to be judged again, from all its points.
        all[k].kinematic = std::move(joint);
        judged.clear();
        taken = all[k].indices;
      }
      absorbExplained(points, neighborhoods, result, labels, static_cast<std::int32_t>(k), all[k],
                      std::move(taken));
      changed = true;
      break;  // the adjacency has changed
    }
  }
  all.erase(
      std::remove_if(all.begin(), all.end(), [](const Segment& s) { return s.indices.empty(); }),
      all.end());
}

}  // namespace

std::size_t mergeKinematicSurfaces(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                   const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                                   const Neighborhoods& neighborhoods, SegmentationResult& result) {
  const std::size_t count = result.segments.size();
  if (count < 2)
    return 0;
  std::vector<MotionHint> hints;
  for (const Segment& s : result.segments)
    hints.push_back(hintOf(s.fit.refined));
  // Curved segments first. Then each plane joins the group of a curved neighbour when it lies
  // along the group's axis (that of its largest curved segment: pairwise checks could chain a
  // spurious axis in) and has at most kPlaneShare times the group's curved points. A plane is a
  // surface of revolution about any axis along its normal and an extrusion along any direction in
  // it: a ground plate with a part standing on it, or with a piece whose fitted axis came out
  // wrong, would be one kinematic surface; the simplest model first keeps it a plane. An extruded
  // section's flats are no larger than a few of its curved strips.
  constexpr std::size_t kPlaneShare = 4;
  UnionFind groups(count);
  const auto pairs = adjacentPairs(neighborhoods, result.labels);
  const double reach = 10.0 * result.distance;  // a sphere's centre on a line
  const auto isPlane = [&](std::size_t k) { return hints[k].kind == MotionHint::direction; };
  for (const auto& [a, b] : pairs)
    if (!isPlane(a) && !isPlane(b) && sameMotion(hints[a], hints[b], reach))
      groups.join(a, b);
  std::vector<std::size_t> curved_points(count, 0), largest(count, count);
  for (std::size_t k = 0; k < count; ++k) {
    if (isPlane(k) || hints[k].kind != MotionHint::line)
      continue;
    const std::size_t root = groups.find(k), size = result.segments[k].indices.size();
    curved_points[root] += size;
    if (largest[root] == count || size > result.segments[largest[root]].indices.size())
      largest[root] = k;
  }
  // A plane joins every adjacent group it lies along (the flats of an extruded section link its
  // curved strips), when it has at most kPlaneShare times their curved points together.
  std::map<std::size_t, std::vector<std::size_t>> along;  // plane → the groups' roots
  for (const auto& [a, b] : pairs) {
    if (isPlane(a) == isPlane(b))
      continue;
    const std::size_t plane = isPlane(a) ? a : b, root = groups.find(isPlane(a) ? b : a);
    if (largest[root] != count && sameMotion(hints[largest[root]], hints[plane], reach))
      along[plane].push_back(root);
  }
  for (auto& [plane, roots] : along) {
    std::sort(roots.begin(), roots.end());
    roots.erase(std::unique(roots.begin(), roots.end()), roots.end());
    std::size_t curved = 0;
    for (const std::size_t root : roots)
      curved += curved_points[root];
    if (result.segments[plane].indices.size() > kPlaneShare * curved)
      continue;
    for (const std::size_t root : roots)
      groups.join(plane, root);
  }
  std::map<std::size_t, std::vector<std::size_t>> members;
  for (std::size_t k = 0; k < count; ++k)
    members[groups.find(k)].push_back(k);

  std::vector<Segment> kept, made;
  std::vector<char> used(count, 0);
  for (const auto& [root, members_of] : members) {
    std::vector<std::size_t> group = members_of;
    std::optional<KinematicFit> fit;
    std::vector<int> indices;
    // Classified, then again without the caps a surface of revolution or a helix took: the
    // simplest model first keeps them planes.
    for (int attempt = 0; attempt < 2; ++attempt) {
      // A group of one, or of planes alone, stays as it is.
      const bool curved = std::any_of(group.begin(), group.end(), [&](std::size_t k) {
        return hints[k].kind == MotionHint::line;
      });
      if (group.size() < 2 || !curved) {
        fit.reset();
        break;
      }
      indices.clear();
      for (const std::size_t k : group) {
        const auto& idx = result.segments[k].indices;
        indices.insert(indices.end(), idx.begin(), idx.end());
      }
      std::sort(indices.begin(), indices.end());
      fit = classifyGroup(points, normals, indices);
      if (!fit || attempt == 1)
        break;
      const std::vector<std::size_t> kept_members = withoutCaps(points, result, group, *fit);
      if (kept_members.size() == group.size())
        break;
      group = kept_members;
    }
    if (!fit)
      continue;
    std::size_t largest = group.front();
    for (const std::size_t k : group)
      if (result.segments[k].indices.size() > result.segments[largest].indices.size())
        largest = k;
    Segment s = result.segments[largest];
    s.indices = std::move(indices);
    s.kinematic = std::move(fit);
    s.slippage.reset();
    for (const std::size_t k : group)
      used[k] = 1;
    made.push_back(std::move(s));
  }
  const std::size_t made_count = made.size();
  if (made_count == 0)
    return 0;
  for (std::size_t k = 0; k < count; ++k)
    if (!used[k])
      kept.push_back(std::move(result.segments[k]));
  // Relabel: the kinematic segments first take the unassigned points their surfaces explain.
  std::vector<std::int32_t>& labels = result.labels;
  std::fill(labels.begin(), labels.end(), -1);
  std::vector<Segment> all = std::move(kept);
  for (Segment& s : made)
    all.push_back(std::move(s));
  for (std::size_t k = 0; k < all.size(); ++k)
    for (const int i : all[k].indices)
      labels[static_cast<std::size_t>(i)] = static_cast<std::int32_t>(k);
  for (std::size_t k = 0; k < all.size(); ++k)
    if (all[k].kinematic)
      absorbExplained(points, neighborhoods, result, labels, static_cast<std::int32_t>(k), all[k],
                      all[k].indices);
  absorbFragments(points, normals, neighborhoods, result, labels, all);
  // Largest first (ties: the lowest first index), and the distances of the members.
  std::vector<std::size_t> order(all.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (all[a].indices.size() != all[b].indices.size())
      return all[a].indices.size() > all[b].indices.size();
    return all[a].indices.front() < all[b].indices.front();
  });
  result.segments.clear();
  for (const std::size_t k : order)
    result.segments.push_back(std::move(all[k]));
  for (std::size_t k = 0; k < result.segments.size(); ++k) {
    Segment& s = result.segments[k];
    std::optional<KinematicProjector> surface;
    if (s.kinematic)
      surface.emplace(s.kinematic->surface);
    double sum = 0.0;
    s.max_distance = 0.0;
    for (const int i : s.indices) {
      labels[static_cast<std::size_t>(i)] = static_cast<std::int32_t>(k);
      const Eigen::Vector3d p = points.col(i);
      const double d = surface ? surface->distance(p) : distance(p, s);
      sum += d * d;
      s.max_distance = std::max(s.max_distance, d);
    }
    s.rms_distance = std::sqrt(sum / static_cast<double>(s.indices.size()));
  }
  return made_count;
}

}  // namespace slipfit
