#pragma once
/// \file A simulated range sensor: rays cast exactly at a scene of bounded primitives
/// (sensor_scene.h), each return displaced along its ray by the sensor's published noise model,
/// into an organized grid with holes and the true primitive of every return.
///
/// - depth_camera: a pinhole (640 × 480, focal 525 px: Kinect v1, PCL's OpenNI grabber) placed
///   0.6–3 m from the scene's focus, looking at it. Axial noise σ(z) = a + b (z − z0)² (Nguyen,
///   Izadi & Lovell 2012: a = 1.2 mm, b = 1.9 mm/m², z0 = 0.4 m) on the depth z; the noisy depth
///   then recorded on disparity levels z = f B / (k · step), k an integer (baseline B = 7.5 cm,
///   step 1/8 px: levels z² step / (f B) apart, 3.2 mm at 1 m, 29 mm at 3 m), and optionally
///   stored in whole `depth_unit`s (millimetres, as OpenNI does); no return outside
///   [min_range, max_range] (0.5–4.5 m).
/// - lidar: a terrestrial scanner 1.5–2 m above the ground near the focus, rays on an angular
///   grid (azimuth all around, elevation −40° … +30°); Gaussian range noise along the ray.
/// - airborne: parallel scan lines across the flight (±20° off nadir) from `altitude`, the
///   aircraft moving one line's footprint between lines; Gaussian range noise along the ray.
///
/// Every sensor: no return where the ray meets the surface more than `max_incidence` off its
/// normal (grazing), and a random `dropout` of the others. The noise is along the ray, not along
/// the normal: anisotropic across a surface seen obliquely, as real sensors are.

#include "slipfit/core/angle_units.h"
#include "slipfit/core/parameter_declaration.h"
#include "slipfit/sampling/sensor_scene.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

namespace slipfit {

enum class RangeSensorKind { depth_camera, lidar, airborne };
constexpr std::array<std::pair<RangeSensorKind, std::string_view>, 3> kRangeSensorNames{{
    {RangeSensorKind::depth_camera, "depth_camera"},
    {RangeSensorKind::lidar, "lidar"},
    {RangeSensorKind::airborne, "airborne"},
}};

struct RangeSensorParameters {
  RangeSensorKind sensor = RangeSensorKind::depth_camera;
  /// Columns and rows of the grid; automatic: 640 × 480 (depth camera), 1800 × 350 (lidar: 0.2°
  /// steps), 800 × rows covering the ground (airborne).
  std::optional<std::size_t> width, height;
  /// Depth camera: horizontal distance from the focus, drawn in [distance_min, distance_max].
  double distance_min = 0.8, distance_max = 2.5;
  double focal =
      525.0;  ///< depth camera: focal length in pixels at 640 columns (scaled with width)
  double baseline = 0.075;        ///< depth camera: projector–camera baseline B, metres
  double disparity_step = 0.125;  ///< depth camera: disparity resolution, pixels (0: no levels)
  double depth_unit = 0.0;  ///< depth camera: depth stored in whole units of this (0: not rounded)
  double noise_a = 0.0012, noise_b = 0.0019, noise_z0 = 0.4;  ///< depth camera: σ(z) model
  /// LiDAR range noise σ along the ray; automatic: 5 mm (lidar), 2 cm (airborne).
  std::optional<double> range_noise;
  double altitude = 80.0;                 ///< airborne: flying height above the ground, metres
  double max_incidence = 80.0 * kDegree;  ///< no return beyond this angle to the normal
  double dropout = 0.0;                   ///< fraction of the other returns lost at random
  /// Fewer returns than this on a true primitive: its points get the truth label −1 (too small
  /// to be segmented, not scored).
  std::size_t truth_min_points = 50;

  /// Each user-facing field with its one declaration (parameter_declaration.h).
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit(self.sensor,
          parameter("sensor",
                    "depth_camera: a Kinect-like pinhole with its published noise and disparity "
                    "levels; lidar: a terrestrial scanner on an angular grid; airborne: scan "
                    "lines from above."),
          kRangeSensorNames);
    visit(self.width,
          parameter("width", "Grid columns (auto: 640 camera, 1800 lidar, 800 airborne).")
              .in("pixels")
              .between(2, 20000));
    visit(self.height,
          parameter("height", "Grid rows (auto: 480 camera, 350 lidar, airborne: the ground).")
              .in("pixels")
              .between(2, 20000));
    visit(self.distance_min,
          parameter("distance_min", "Depth camera: least horizontal distance to the scene's focus.")
              .in("m")
              .above(0));
    visit(self.distance_max,
          parameter("distance_max", "Depth camera: largest horizontal distance (≥ distance_min).")
              .in("m")
              .above(0));
    visit(self.focal,
          parameter("focal", "Depth camera: focal length at 640 columns.").in("pixels").above(0));
    visit(self.baseline,
          parameter("baseline", "Depth camera: projector–camera baseline.").in("m").above(0));
    visit(
        self.disparity_step,
        parameter("disparity_step", "Depth camera: disparity resolution (0: depth not on levels).")
            .in("pixels")
            .between(0, 1));
    visit(self.depth_unit,
          parameter("depth_unit",
                    "Depth camera: depth stored in whole units of this, after the levels (OpenNI "
                    "and RealSense store millimetres: 0.001; 0: not rounded).")
              .in("m")
              .between(0, 0.1));
    visit(self.noise_a,
          parameter("noise_a", "Depth camera: σ(z) = a + b (z − z0)², a.").in("m").atLeast(0));
    visit(self.noise_b,
          parameter("noise_b", "Depth camera: σ(z) = a + b (z − z0)², b.").in("m/m²").atLeast(0));
    visit(self.noise_z0,
          parameter("noise_z0", "Depth camera: σ(z) = a + b (z − z0)², z0.").in("m").atLeast(0));
    visit(self.range_noise,
          parameter("range_noise", "LiDAR: σ of the range noise (auto: 5 mm lidar, 2 cm airborne).")
              .in("m")
              .atLeast(0));
    visit(self.altitude,
          parameter("altitude", "Airborne: flying height above the ground.").in("m").above(1));
    visit(self.max_incidence,
          parameter("max_incidence", "No return beyond this angle between the ray and the normal.")
              .in("deg", kDegree)
              .between(1, 90));
    visit(self.dropout,
          parameter("dropout", "Fraction of the other returns lost at random.").between(0, 0.9));
    visit(self.truth_min_points,
          parameter("truth_min_points",
                    "A true primitive with fewer returns gets truth label -1 (not scored).")
              .in("points")
              .between(1, 1e9));
  }

  /// Throws InvalidParameterError naming the field.
  void validate() const;
};

/// An organized scan: row-major grid, NaN where there is no return.
struct RangeScan {
  std::size_t width = 0, height = 0;
  Eigen::Matrix3Xd points;           ///< 3 × (width · height), NaN columns for no return
  std::vector<std::int32_t> labels;  ///< true primitive per cell, −1 for none (or too small)
  std::vector<std::int32_t> types;   ///< its PrimitiveType as an integer, −1 for none
  Eigen::Matrix3Xd normals;          ///< the exact surface normal at each return (NaN: none)
  std::vector<Primitive> truth;      ///< the true primitives, indexed by label
  /// The sensor pose in PCL's convention (sensor_origin_, sensor_orientation_; the camera frame x
  /// right, y down, z forward). A depth camera's scan is in its own frame, as a camera delivers
  /// it (points, normals and truth; the pose is then the identity at the origin); a LiDAR scan is
  /// in the scene's frame, airborne from the middle of the flight line.
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  std::size_t returns = 0;  ///< cells with a return
};

/// Scans \a scene with the sensor of \a parameters, its pose and noise drawn from \a seed.
/// Deterministic for given arguments, whatever \a threads (threads.h: 0 for all cores).
RangeScan scanScene(const SensorScene& scene, const RangeSensorParameters& parameters,
                    std::uint64_t seed, int threads = 0);

}  // namespace slipfit
