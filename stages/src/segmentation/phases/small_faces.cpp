// Phase 9 (recover_small_faces): patches of free points that no adjacent primitive explains,
// fitted as faces too small to have seeded.
#include "phases.h"

#include "slipfit/fitting/model_selection.h"
#include "slipfit/segmentation/segmentation_tuning.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace slipfit::phases {

namespace {

using T = SegmentationTuning;

/// Each point of \a set gets in \a own the normal of its neighbors within the set (itself and at
/// least three others, \a known set; else the cloud's normal, \a known cleared): at a face a few
/// rows wide every neighborhood straddles its edges, and normals estimated over them lead the
/// closed forms astray (a hole's wall fitted as a cylinder from such normals left an RMS of a fifth
/// of its radius).
void estimateOwnNormals(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                        const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                        const Neighborhoods& hoods, const std::vector<int>& set,
                        std::vector<std::uint32_t>& stamp, std::uint32_t generation,
                        Eigen::Matrix3Xd& own, std::vector<char>& known) {
  for (int i : set)
    stamp[static_cast<std::size_t>(i)] = generation;
  for (int i : set) {
    Eigen::Vector3d mean = points.col(i);
    Eigen::Matrix3d second = points.col(i) * points.col(i).transpose();
    int count = 1;
    for (pcl::index_t j : hoods[static_cast<std::size_t>(i)])
      if (j != i && stamp[static_cast<std::size_t>(j)] == generation) {
        mean += points.col(j);
        second += points.col(j) * points.col(j).transpose();
        ++count;
      }
    own.col(i) = normals.col(i);
    known[static_cast<std::size_t>(i)] = count >= 4;
    if (count < 4)
      continue;
    mean /= count;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(second / count -
                                                               mean * mean.transpose());
    own.col(i) = eigen.eigenvectors().col(0);
  }
}

/// The simplest adequate primitive of the points \a set with the normals \a own (an evenly
/// strided RegionGrower::kTypeSubset of them decide, as in RegionGrower::fitBest).
FitResult fitSet(const Eigen::Ref<const Eigen::Matrix3Xd>& points, const Eigen::Matrix3Xd& own,
                 const std::vector<int>& set) {
  const std::size_t stride = std::max<std::size_t>(1, set.size() / RegionGrower::kTypeSubset);
  std::vector<int> subset;
  for (std::size_t k = 0; k < set.size(); k += stride)
    subset.push_back(set[k]);
  return fitAuto(points(Eigen::all, subset), own(Eigen::all, subset),
                 Eigen::VectorXd::Ones(static_cast<Eigen::Index>(subset.size())));
}

/// Phase 9's search, with its scratch arrays: patches of free points, tried whole and then face by
/// face.
class SmallFaces {
 public:
  explicit SmallFaces(SegmentationState& s)
      : s_(s),
        grower_(*s.grower),
        seen_(s.n, 0),
        used_(s.n, 0),
        stamp_(s.n, 0),
        own_(3, static_cast<Eigen::Index>(s.n)),
        known_(s.n, 0),
        cos_angle_(std::cos(s.result.max_angle)),
        // Faces recovered here do not vouch for the density of others: outliers would vouch for
        // outliers.
        grown_spacing_(s.regionSpacings()) {}

  /// Tries the connected patch of free points from free point \a start (not seen yet): whole, and
  /// when no one primitive explains it, face by face.
  void searchPatch(std::size_t start) {
    std::vector<int> patch{static_cast<int>(start)};
    seen_[start] = 1;
    for (std::size_t head = 0; head < patch.size(); ++head)
      forEachFreeNear(patch[head], [&](int j) {
        if (!seen_[static_cast<std::size_t>(j)]) {
          seen_[static_cast<std::size_t>(j)] = 1;
          patch.push_back(j);
        }
      });
    if (patch.size() < T::smallest_patch || tryFace(patch, s_.local_types[start], false))
      return;
    for (int seed : patch)
      if (s_.isFree(seed) && !used_[static_cast<std::size_t>(seed)])
        searchFrom(seed);
  }

  bool recovered() const { return recovered_; }
  bool seen(std::size_t i) const { return seen_[i] != 0; }

 private:
  /// The free points among the neighbors of free point i and among those of its labelled
  /// neighbors: a wall whose free rows are cut by the edge rows the faces took stays one patch.
  template <typename Visit>
  void forEachFreeNear(int i, const Visit& visit) const {
    for (pcl::index_t j : s_.hood(i)) {
      if (s_.isFree(j)) {
        visit(j);
        continue;
      }
      for (pcl::index_t l : s_.hood(j))
        if (s_.isFree(l))
          visit(l);
    }
  }

  /// The face from \a seed: the free points of its two rings within the patch (seen), grown over
  /// the patch by their fit.
  void searchFrom(int seed) {
    const auto us = static_cast<std::size_t>(seed);
    ++generation_;
    std::vector<int> face{seed};
    stamp_[us] = generation_;
    for (std::size_t head = 0; head < face.size() && head < 1 + s_.hood(seed).size(); ++head)
      forEachFreeNear(face[head], [&](int j) {
        const auto uj = static_cast<std::size_t>(j);
        if (seen_[uj] && stamp_[uj] != generation_) {
          stamp_[uj] = generation_;
          face.push_back(j);
        }
      });
    // Each point seeds once, and the two rings of a seed that no primitive fits seed no more.
    used_[us] = 1;
    if (face.size() < T::smallest_patch)
      return;
    // Scattered outliers fail before any fit is made (tryFace checks the grown face again);
    // their points may still seed rings of their own.
    if (s_.isScattered(face, grown_spacing_, stamp_, generation_))
      return;
    const FitResult fit = grower_.fitBest(face);
    if (!fit.ok()) {
      for (int i : face)
        used_[static_cast<std::size_t>(i)] = 1;
      return;
    }
    face.erase(std::remove_if(face.begin(), face.end(),
                              [&](int i) { return !grower_.near(i, fit.refined); }),
               face.end());
    ++generation_;
    for (int i : face)
      stamp_[static_cast<std::size_t>(i)] = generation_;
    for (std::size_t head = 0; head < face.size(); ++head)
      forEachFreeNear(face[head], [&](int j) {
        const auto uj = static_cast<std::size_t>(j);
        if (seen_[uj] && stamp_[uj] != generation_ && grower_.near(j, fit.refined)) {
          stamp_[uj] = generation_;
          face.push_back(j);
        }
      });
    for (int i : face)
      used_[static_cast<std::size_t>(i)] = 1;
    tryFace(face, s_.local_types[us], true);
  }

  /// Tries the free points \a face as one region; true when it becomes one.
  bool tryFace(const std::vector<int>& face, SlippageType seed_type, bool check_normals) {
    if (face.size() < T::smallest_patch)
      return false;
    ++generation_;
    std::vector<int> rim;  // labelled neighbours of the face
    for (int i : face)
      for (pcl::index_t j : s_.hood(i)) {
        const auto uj = static_cast<std::size_t>(j);
        if (!s_.isFree(j) && stamp_[uj] != generation_) {
          stamp_[uj] = generation_;
          rim.push_back(j);
        }
      }
    std::sort(rim.begin(), rim.end());
    // Outliers scattered through the volume are free points too (THEORY §6, phase 9).
    if (s_.isScattered(face, grown_spacing_, stamp_, generation_))
      return false;
    estimateOwnNormals(s_.points, s_.normals, s_.hoods, face, stamp_, ++generation_, own_, known_);
    FitResult fit = fitSet(s_.points, own_, face);
    std::vector<int> members, edges;
    for (int round = 0; round < 2 && fit.ok(); ++round) {
      members.clear();
      for (int i : face)
        if (grower_.near(i, fit.refined) &&
            (!check_normals || !known_[static_cast<std::size_t>(i)] ||
             std::abs(surfaceNormal(s_.points.col(i), fit.refined).dot(own_.col(i))) >= cos_angle_))
          members.push_back(i);
      edges.clear();
      for (int j : rim) {
        const double d = distance(s_.points.col(j), fit.refined);
        if (d <= grower_.tolerance(j) &&
            d <= distance(s_.points.col(j), s_.primitive(s_.label(j))) + s_.edge_margin)
          edges.push_back(j);
      }
      if (round == 1)
        break;
      std::vector<int> all = members;
      all.insert(all.end(), edges.begin(), edges.end());
      estimateOwnNormals(s_.points, s_.normals, s_.hoods, all, stamp_, ++generation_, own_, known_);
      FitResult refit = fitSet(s_.points, own_, all);
      if (!refit.ok())
        break;
      fit = std::move(refit);
    }
    if (!fit.ok() ||
        static_cast<double>(members.size()) < T::held * static_cast<double>(face.size()) ||
        members.size() < 3 * static_cast<std::size_t>(parameterCount(fit.type)) ||
        members.size() + edges.size() < s_.result.min_points)
      return false;
    members.insert(members.end(), edges.begin(), edges.end());
    s_.addRegion(std::move(members), std::move(fit), seed_type);
    recovered_ = true;
    return true;
  }

  SegmentationState& s_;
  RegionGrower& grower_;
  std::vector<char> seen_, used_;
  std::vector<std::uint32_t> stamp_;
  std::uint32_t generation_ = 0;
  Eigen::Matrix3Xd own_;  ///< normals estimated within a face (estimateOwnNormals)
  std::vector<char> known_;
  double cos_angle_;
  std::vector<double> grown_spacing_;
  bool recovered_ = false;
};

}  // namespace

void recoverSmallFaces(SegmentationState& s) {
  // Free points left after the crease pass are within tolerance of no adjacent primitive. A
  // connected patch of them is a face too small to have seeded (the wall of a hole two rows of
  // points deep, a narrow fillet: every neighborhood there straddles an edge), and its edge rows
  // were taken by the faces around it. The patch is fitted with the simplest adequate type; the
  // edge points it explains as well as their own primitive (a tie within s/20, see shareEdges)
  // join it, and the type is chosen again with them (two rows of a hole lie on a sphere too, four
  // do not). The patch becomes a region when the fit holds most of its own points and three per
  // parameter, and with its edges it reaches min_points. A patch that no one primitive explains
  // (a row of narrow faces, each too small to seed) is tried face by face: from each of its
  // points in turn, the free points of its two rings grown over the patch by their fit.
  SmallFaces search(s);
  for (std::size_t i = 0; i < s.n; ++i)
    if (s.result.labels[i] < 0 && !search.seen(i))
      search.searchPatch(i);
  if (search.recovered())
    s.relabelFromRegions();
}

}  // namespace slipfit::phases
