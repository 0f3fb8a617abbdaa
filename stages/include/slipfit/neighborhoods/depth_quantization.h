#pragma once
/// \file Detection of a coordinate recorded on a lattice of levels: the depth of structured-light
/// and time-of-flight cameras (a Kinect stores depth in steps that grow with z², about 3 mm at
/// 1 m and 26 mm at 3 m), or any coordinate rounded coarsely. Neighborhoods that lie within one
/// level see a flat slice of the surface, not the surface; tolerances below the step split one
/// surface into its slices.

#include <Eigen/Core>

#include <cmath>
#include <string>
#include <vector>

namespace slipfit {

/// The levels of a quantized coordinate axis and the local step at each level.
struct QuantizedAxis {
  /// 0, 1 or 2 (x, y, z); kAlongDirection for levels across `direction`, off the coordinate axes
  /// (a depth frame registered into another frame); −1 when nothing is quantized.
  int axis = -1;
  static constexpr int kAlongDirection = 3;
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  ///< unit; with kAlongDirection
  /// With kAlongDirection: two points whose coordinates along `direction` differ by at most this
  /// are on one level (the rounding of the stored coordinates); 0 on a coordinate axis (equal).
  double level_span = 0.0;
  std::vector<double> levels;  ///< the values that hold the points, ascending
  std::vector<double> steps;   ///< the local step at each level (cloud units)

  bool detected() const { return axis >= 0; }
  /// The coordinate of \a p the levels are counted in.
  double along(const Eigen::Vector3d& p) const {
    return axis == kAlongDirection ? direction.dot(p) : p(axis);
  }
  /// Whether \a a and \a b lie on one level.
  bool sameLevel(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
    return axis == kAlongDirection ? std::abs(along(a) - along(b)) <= level_span
                                   : a(axis) == b(axis);
  }
  /// "coordinate z", or "the coordinate along (0.34, -0.47, 0.81)": for reports.
  std::string name() const;
  /// The local step at coordinate \a value along the axis (the nearest level's); 0 when no axis
  /// is quantized.
  double stepAt(double value) const;
  /// The local step at point \a p; 0 when no axis is quantized.
  double stepAt(const Eigen::Vector3d& p) const { return detected() ? stepAt(along(p)) : 0.0; }
  double minStep() const;
  double maxStep() const;
};

/// An axis is quantized when at least 99 % of the points lie on values shared by 8 or more points,
/// on at least 16 such levels whose consecutive steps change slowly (the median ratio of
/// neighboring steps within 2): a lattice, not a few flat faces of a CAD part. The coarsest such
/// axis is returned when its median step is at least 4 × that of any other lattice axis: axes on
/// lattices of like steps are a regular grid sampling, not a depth sensor's levels (then none is
/// returned). Non-finite points are ignored. When no coordinate axis holds a lattice, levels
/// across a direction are looked for (latticeAcross in the source: a depth frame registered into
/// a world frame, whose levels are planes across the camera's axis): the direction from local
/// patches of 12 points that lie on one plane to the rounding of their coordinates, refined on
/// the levels it finds, whose points must then pass the same rules, a level spanning no more than
/// the rounding.
/// \param points 3×N coordinates.
QuantizedAxis detectQuantizedAxis(const Eigen::Ref<const Eigen::Matrix3Xd>& points);

}  // namespace slipfit
