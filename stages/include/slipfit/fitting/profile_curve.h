#pragma once
/// \file A curve through 2D points sampled along it with noise: the profile of a kinematic surface
/// (the meridian of a surface of revolution, the cross-section of an extrusion, the unscrewed
/// section of a helical surface; kinematic_surface.h maps the 3D points to these planes). The curve
/// is a polyline, open or closed, fitted by least squares with as few vertices as the noise allows
/// (docs/THEORY.md §5.5). Pure Eigen, no 3D.

#include <Eigen/Core>

#include <string>
#include <vector>

namespace slipfit {

/// A polyline in the profile plane. Open: vertices[0] … vertices[V − 1]; closed: the segment
/// from the last vertex back to the first is part of it.
struct ProfileCurve {
  std::vector<Eigen::Vector2d> vertices;
  bool closed = false;

  /// Segments: V − 1 open, V closed.
  std::size_t segmentCount() const;
  /// Each vertex's two coordinates: 2 V.
  int parameterCount() const { return 2 * static_cast<int>(vertices.size()); }
};

/// The distance from \a q to \a curve in the metric that scales the first coordinate by
/// \a first_scale (1: Euclidean; kinematic_surface.h's helical metric otherwise), and, when
/// \a period > 0, the least over q and its images q ± (period, 0) (a profile on a periodic strip).
/// Infinity for a curve without vertices.
double profileDistance(const ProfileCurve& curve, const Eigen::Vector2d& q,
                       double first_scale = 1.0, double period = 0.0);

/// Where \a q meets \a curve in profileDistance's metric: the distance, the nearest segment (from
/// vertex `segment` to the next) and the parameter t ∈ [0, 1] along it, and the unit vector from
/// the nearest point to q in the scaled metric (zero on the curve): the distance's derivative with
/// respect to the segment's two vertices is −(1 − t) Mu and −t Mu, M = diag(first_scale, 1).
struct ProfileProjection {
  double distance = 0.0;
  std::size_t segment = 0;
  double t = 0.0;
  Eigen::Vector2d unit = Eigen::Vector2d::Zero();
};
ProfileProjection projectOnProfile(const ProfileCurve& curve, const Eigen::Vector2d& q,
                                   double first_scale = 1.0, double period = 0.0);

/// projectOnProfile for many points on one curve: the segments binned on a uniform grid over the
/// curve's box (cells of at least the mean segment length and 1/128 of the box), searched ring by
/// ring from the query's cell until the ring's least possible distance, first_scale × (ring − 1) ×
/// cell, passes the best found. Exact: the same projection as projectOnProfile (ties go to the
/// lower image, then the lower segment, as there), in O(1) segments a query for a point near the
/// curve instead of all of them. \a first_scale ≤ 1 (the helical metric's is).
class ProfileIndex {
 public:
  explicit ProfileIndex(const ProfileCurve& curve, double period = 0.0);
  ProfileProjection project(const Eigen::Vector2d& q, double first_scale = 1.0) const;

 private:
  struct Best;
  void search(const Eigen::Vector2d& p, double first_scale, int image, Best& best) const;

  const ProfileCurve* curve_;
  double period_ = 0.0;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  double cell_ = 1.0;
  int nx_ = 0, ny_ = 0;
  std::vector<std::size_t> offsets_, segments_;  ///< per cell (CSR), the segments crossing it
};

/// One least-squares update of \a curve's vertices to the points \a q (each point at its nearest
/// segment's parameter; a light second-difference penalty; a vertex where the polyline turns back
/// dropped): step 3 of fitProfileCurve, for a curve fitted before to points that have moved a
/// little (kinematic_fit.h refits the profile as the motion changes).
void refineProfileCurve(const Eigen::Ref<const Eigen::Matrix2Xd>& q, ProfileCurve& curve);

/// The noise σ across a curve sampled by 2 × N points \a q, from the points alone, given an upper
/// guess \a guess > 0 of it: at up to 2000 of the points (every ⌈N / 2000⌉-th), a parabola across
/// the local principal direction fitted to the points within R = 8 × the current estimate (the
/// 256 nearest at most, 8 at least), its residual variance over m − 3 degrees of freedom; σ is the
/// root of their median over the median of χ²₍ₘ₋₃₎ / (m − 3). Started at the guess and repeated
/// while the estimate falls by more than 10 % (4 times at most): neighbourhoods 8 σ wide span the
/// curve's thickness four times over, so the principal direction is the curve's, and a parabola
/// over them holds the curve's bending once R is down to its scale. 0 for fewer than 8 points.
double estimateProfileNoise(const Eigen::Ref<const Eigen::Matrix2Xd>& q, double guess);

/// The outcome of fitProfileCurve.
struct ProfileFit {
  ProfileCurve curve;
  bool ok = false;
  std::string reason;         ///< why not, when !ok
  double rms_distance = 0.0;  ///< over the points, Euclidean
};

/// Fits a polyline to 2 × N points \a q spread along a curve with noise \a noise (σ across it,
/// ≥ 0; 0 means exact points, the spacing then sets the scale). With b = max(4σ, 16 D / N,
/// D / 400) (D the points' bounding-box diagonal: about 8 points per b on a curve 2 D long):
///  1. nodes: a cover of the points by discs of radius b (each point not yet covered starts one),
///     each node at the centroid of its disc — across a noisy curve thinner than b, one node;
///  2. order: the nodes' minimum spanning tree over pairs up to 3 b apart (small holes in the
///     coverage bridged); its longest path (the tree's diameter), closed when its ends are
///     within 4 b and it is at least 8 b long (a loop's tree misses one edge of it);
///  3. vertices: the path resampled every b of its length, refined by linear least squares (each
///     point at its nearest segment's parameter, a light second-difference penalty; a vertex
///     where the polyline turns back dropped), simplified by Douglas–Peucker at σ (b / 50 for
///     exact points), and refined again.
/// Fails (ok false, with the reason) for fewer than 10 finite points, or points on one spot.
ProfileFit fitProfileCurve(const Eigen::Ref<const Eigen::Matrix2Xd>& q, double noise);

}  // namespace slipfit
