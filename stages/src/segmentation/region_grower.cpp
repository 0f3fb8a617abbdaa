#include "slipfit/segmentation/region_grower.h"

#include "slipfit/core/median.h"
#include "slipfit/fitting/model_selection.h"
#include "slipfit/fitting/primitives.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace slipfit {

RegionGrower::RegionGrower(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                           const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                           const Neighborhoods& hoods, std::vector<double> tolerance,
                           double max_angle)
    : points_(points),
      normals_(normals),
      hoods_(hoods),
      tolerance_(std::move(tolerance)),
      cos_angle_(std::cos(max_angle)),
      stamp_(static_cast<std::size_t>(points.cols()), 0) {}

bool RegionGrower::near(int i, const Primitive& primitive) const {
  return distance(points_.col(i), primitive) <= tolerance(i);
}

bool RegionGrower::accepts(int i, const Primitive& primitive) const {
  const Eigen::Vector3d p = points_.col(i);
  if (!(distance(p, primitive) <= tolerance(i)))
    return false;
  return std::abs(surfaceNormal(p, primitive).dot(normals_.col(i))) >= cos_angle_;
}

FitResult RegionGrower::fit(PrimitiveType type, const std::vector<int>& members, bool all) const {
  Eigen::Matrix3Xd p, n;
  gather(members, all, p, n, kSubset);
  return fitPrimitive(type, p, n, Eigen::VectorXd::Ones(p.cols()));
}

FitResult RegionGrower::screen(PrimitiveType type, const std::vector<int>& members) const {
  Eigen::Matrix3Xd p, n;
  gather(members, false, p, n, kTypeSubset);
  return fitPrimitive(type, p, n, Eigen::VectorXd::Ones(p.cols()));
}

double RegionGrower::smallestTolerance(const std::vector<int>& members) const {
  double floor = std::numeric_limits<double>::infinity();
  for (int i : members)
    floor = std::min(floor, tolerance(i));
  return floor;
}

Eigen::VectorXd RegionGrower::precisionWeights(const std::vector<int>& members) const {
  Eigen::VectorXd w(static_cast<Eigen::Index>(members.size()));
  const double floor = smallestTolerance(members);
  for (Eigen::Index j = 0; j < w.size(); ++j) {
    const double relative = floor / tolerance(members[static_cast<std::size_t>(j)]);
    w(j) = relative * relative;
  }
  return w;
}

FitResult RegionGrower::fitByPrecision(PrimitiveType type, const std::vector<int>& members) const {
  Eigen::Matrix3Xd p, n;
  gather(members, true, p, n, kSubset);
  return fitPrimitive(type, p, n, precisionWeights(members));
}

FitResult RegionGrower::fitNear(const Primitive& start, const std::vector<int>& members) const {
  Eigen::Matrix3Xd p, n;
  gather(members, false, p, n, kTypeSubset);
  FitResult r = fitFrom(start, p, Eigen::VectorXd::Ones(p.cols()));
  if (r.ok() && isNearlyDegenerate(r.refined, p)) {
    r.status = FitStatus::degenerate;
    r.reason = std::string(primitiveTypeName(r.type)) + " fit: in its simpler limit";
  }
  return r;
}

bool RegionGrower::simplerTypeIsAdequate(PrimitiveType type, double rms,
                                         const std::vector<int>& members) const {
  Eigen::Matrix3Xd p, n;
  gather(members, false, p, n, kTypeSubset);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(p.cols());
  for (const auto& [simpler, name] : kPrimitiveTypeNames) {
    if (parameterCount(simpler) >= parameterCount(type))
      continue;
    const FitResult r = fitPrimitive(simpler, p, n, ones);
    if (r.ok() && r.rms_distance <= (1.0 + kAdequacyMargin) * rms &&
        !isNearlyDegenerate(r.refined, p))
      return true;
  }
  return false;
}

FitResult RegionGrower::fitBest(const std::vector<int>& members, bool refine) const {
  Eigen::Matrix3Xd p, n;
  gather(members, false, p, n, kTypeSubset);
  FitOptions options;
  options.refine = refine;
  return fitAuto(p, n, Eigen::VectorXd::Ones(p.cols()), options);
}

double RegionGrower::medianDistance(const std::vector<int>& members,
                                    const Primitive& primitive) const {
  const std::size_t stride = std::max<std::size_t>(1, members.size() / kSubset);
  std::vector<double> d;
  for (std::size_t j = 0; j < members.size(); j += stride)
    d.push_back(distance(points_.col(members[j]), primitive));
  return d.empty() ? 0.0 : medianInPlace(d);
}

FitResult RegionGrower::grow(PrimitiveType type, std::vector<int>& members, FitResult fit,
                             const std::vector<std::int32_t>& labels) {
  ++generation_;
  for (int i : members)
    stamp_[static_cast<std::size_t>(i)] = generation_;
  std::size_t fitted_size = members.size();
  for (std::size_t head = 0; head < members.size(); ++head) {
    const NeighborView v = hoods_[static_cast<std::size_t>(members[head])];
    for (pcl::index_t j : v) {
      const auto uj = static_cast<std::size_t>(j);
      if (stamp_[uj] == generation_ || labels[uj] >= 0)
        continue;
      if (!accepts(j, fit.refined))
        continue;
      stamp_[uj] = generation_;
      members.push_back(j);
    }
    if (members.size() >= 2 * fitted_size) {
      FitResult refit = this->fit(type, members);
      if (refit.ok())
        fit = std::move(refit);
      fitted_size = members.size();
    }
  }
  return fit;
}

void RegionGrower::prune(std::vector<int>& members, const Primitive& primitive) const {
  members.erase(
      std::remove_if(members.begin(), members.end(), [&](int i) { return !accepts(i, primitive); }),
      members.end());
}

void RegionGrower::gather(const std::vector<int>& members, bool all, Eigen::Matrix3Xd& p,
                          Eigen::Matrix3Xd& n, std::size_t subset) const {
  const std::size_t stride = all ? 1 : std::max<std::size_t>(1, members.size() / subset);
  const auto m = static_cast<Eigen::Index>((members.size() + stride - 1) / stride);
  p.resize(3, m);
  n.resize(3, m);
  for (Eigen::Index j = 0; j < m; ++j) {
    const int i = members[static_cast<std::size_t>(j) * stride];
    p.col(j) = points_.col(i);
    n.col(j) = normals_.col(i);
  }
}

}  // namespace slipfit
