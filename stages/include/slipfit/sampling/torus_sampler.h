#pragma once
/// \file Seeded point sampling of a posed torus with analytic normals, noise, outliers and partial
/// coverage: the test-cloud source for the later stages.

#include "slipfit/core/angle_units.h"
#include "slipfit/core/parameter_declaration.h"
#include "slipfit/sampling/sampler_parameters.h"
#include "slipfit/surfaces/torus.h"
#include "slipfit/surfaces/torus_mesh.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

namespace slipfit {

enum class TorusSampling {
  area,      ///< uniform by area: density ∝ the area element r (R + r cos α)
  angle,     ///< uniform in (α, β)
  parameter  ///< uniform in the four quarter patches' (u, v)
};
constexpr std::array<std::pair<TorusSampling, std::string_view>, 3> kTorusSamplingNames{{
    {TorusSampling::area, "area"},
    {TorusSampling::angle, "angle"},
    {TorusSampling::parameter, "parameter"},
}};

struct TorusSamplingParameters {
  TorusShape shape;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< world position of the torus centre
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();   ///< world direction of the symmetry axis
  double spin = 0.0;           ///< rotation about the axis, radians (where β = 0 lies)
  std::size_t points = 10000;  ///< surface samples (outliers come on top), >= 1
  TorusSampling sampling = TorusSampling::area;
  double alpha_min = 0.0;  ///< coverage around the tube, radians, 0 ≤ min < max ≤ 2π
  double alpha_max = 2.0 * kPi;
  double beta_min = 0.0;  ///< coverage around the axis, radians
  double beta_max = 2.0 * kPi;
  double noise = 0.0;             ///< σ of isotropic Gaussian position noise, world units, >= 0
  double normal_noise = 0.0;      ///< σ of normal perturbation, radians, >= 0
  double outlier_fraction = 0.0;  ///< outliers per surface sample, in [0, 1]
  std::uint64_t seed = 1;

  /// Each user-facing field with its one declaration (parameter_declaration.h).
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit(self.shape.R, parameter("major_radius", "R: radius of the centre circle of the tube.")
                            .in("units")
                            .above(0));
    visit(self.shape.r,
          parameter("minor_radius", "r: radius of the tube; 0 < r < R.").in("units").above(0));
    visit(self.center, parameter("center", "Position of the torus centre.").in("units"));
    visit(self.axis, parameter("axis", "Direction of the symmetry axis (normalised)."));
    visit(self.spin, parameter("spin",
                               "Rotation about the axis: where β = 0 lies (matters for partial "
                               "coverage).")
                         .in("deg", kDegree)
                         .between(-360, 360));
    visit(self.points, surfaceSamplesParameter());
    visit(self.sampling,
          parameter("sampling",
                    "area: uniform on the surface (density ∝ R + r cos α); angle: uniform in (α, "
                    "β); parameter: uniform in the Bézier quarters' (u, v)."),
          kTorusSamplingNames);
    visit(self.alpha_min,
          parameter("alpha_min",
                    "Coverage around the tube starts here (α = 0: outer equator, 90: top).")
              .in("deg", kDegree)
              .atLeast(0)
              .below(360));
    visit(self.alpha_max,
          parameter("alpha_max", "Coverage around the tube ends here (above alpha_min).")
              .in("deg", kDegree)
              .above(0)
              .atMost(360));
    visit(self.beta_min,
          parameter("beta_min", "Coverage around the axis starts here (β = 0 on +x).")
              .in("deg", kDegree)
              .atLeast(0)
              .below(360));
    visit(self.beta_max,
          parameter("beta_max", "Coverage around the axis ends here (above beta_min).")
              .in("deg", kDegree)
              .above(0)
              .atMost(360));
    visit(self.noise, positionNoiseParameter());
    visit(self.normal_noise, normalNoiseParameter());
    visit(self.outlier_fraction,
          parameter("outliers",
                    "Outliers per surface sample, uniform in the bounding box with random normals; "
                    "marked by the field 'outlier'.")
              .between(0, 1));
  }

  /// Throws InvalidParameterError naming the field.
  void validate() const;
  /// The rigid motion from the torus frame (axis z through the origin) to the world.
  Eigen::Isometry3d pose() const;
};

/// Samples a torus, PCL style: setParameters(), then sample(). Points carry unit normals
/// (outward for surface samples, random for outliers). The same parameters give the same cloud.
class TorusSampler {
 public:
  /// Checked when the work runs (one validation, PCL's initCompute convention).
  void setParameters(const TorusSamplingParameters& parameters) { parameters_ = parameters; }
  const TorusSamplingParameters& getParameters() const { return parameters_; }

  /// Fills \a cloud; \a outlier (optional) gets 1 for outliers, 0 for surface samples.
  void sample(pcl::PointCloud<pcl::PointNormal>& cloud,
              std::vector<std::int32_t>* outlier = nullptr) const;
  /// The same samples in double precision (3 × N points and unit normals), before the cloud's
  /// float storage rounds them.
  void sample(Eigen::Matrix3Xd& points, Eigen::Matrix3Xd& normals,
              std::vector<std::int32_t>* outlier = nullptr) const;

 private:
  TorusSamplingParameters parameters_;
};

}  // namespace slipfit
