#pragma once
/// \file Detection of a coordinate recorded on a lattice of levels: the depth of structured-light
/// and time-of-flight cameras (a Kinect stores depth in steps that grow with z², about 3 mm at
/// 1 m and 26 mm at 3 m), or any coordinate rounded coarsely. Neighborhoods that lie within one
/// level see a flat slice of the surface, not the surface; tolerances below the step split one
/// surface into its slices.

#include <Eigen/Core>

#include <vector>

namespace slipfit {

/// The levels of a quantized coordinate axis and the local step at each level.
struct QuantizedAxis {
  int axis = -1;               ///< 0, 1 or 2 (x, y, z); −1 when no axis is quantized
  std::vector<double> levels;  ///< the values that hold the points, ascending
  std::vector<double> steps;   ///< the local step at each level (cloud units)

  bool detected() const { return axis >= 0; }
  /// The local step at coordinate \a value along the axis (the nearest level's); 0 when no axis
  /// is quantized.
  double stepAt(double value) const;
  /// The local step at point \a p; 0 when no axis is quantized.
  double stepAt(const Eigen::Vector3d& p) const { return detected() ? stepAt(p(axis)) : 0.0; }
  double minStep() const;
  double maxStep() const;
};

/// An axis is quantized when at least 99 % of the points lie on values shared by 8 or more points,
/// on at least 16 such levels whose consecutive steps change slowly (the median ratio of
/// neighboring steps within 2): a lattice, not a few flat faces of a CAD part. The coarsest such
/// axis is returned when its median step is at least 4 × that of any other lattice axis: axes on
/// lattices of like steps are a regular grid sampling, not a depth sensor's levels (then none is
/// returned). Non-finite points are ignored.
/// \param points 3×N coordinates.
QuantizedAxis detectQuantizedAxis(const Eigen::Ref<const Eigen::Matrix3Xd>& points);

}  // namespace slipfit
