#include "slipfit/sampling/range_scanner.h"

#include "slipfit/core/exceptions.h"
#include "slipfit/core/threads.h"
#include "slipfit/sampling/random_scene_sampler.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace slipfit {

namespace {

using Eigen::Vector3d;

/// A depth camera's working range (Kinect v1), metres; a terrestrial scanner's reach.
constexpr double kCameraNear = 0.5, kCameraFar = 4.5, kLidarFar = 120.0;
/// The terrestrial scanner's elevations, degrees; the airborne scanner's half swath off nadir.
constexpr double kLidarTop = 30.0, kLidarBottom = -40.0, kAirborneHalfSwath = 20.0;

/// SplitMix64: a cell's own random stream from (seed, cell), so that the noise of a cell does
/// not depend on the order or the thread the cells are cast in.
class CellRandom {
 public:
  CellRandom(std::uint64_t seed, std::uint64_t cell)
      : state_(seed * 0x9E3779B97F4A7C15ull ^ (cell + 0x632BE59BD9B4E019ull)) {}
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  /// A standard normal deviate (Box–Muller).
  double gaussian() {
    const double u = std::max(uniform(), 1e-300), v = uniform();
    return std::sqrt(-2.0 * std::log(u)) * std::cos(2.0 * 3.14159265358979323846 * v);
  }

 private:
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  std::uint64_t state_;
};

/// Where the rays start and go: one origin (camera, terrestrial) or one per row (airborne).
struct RayGrid {
  RangeSensorKind kind = RangeSensorKind::depth_camera;
  std::size_t width = 0, height = 0;
  Vector3d eye = Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  ///< columns: right, down, forward
  double fx = 0.0, cx = 0.0, cy = 0.0;                     ///< camera
  double line_spacing = 0.0, line_start = 0.0;             ///< airborne: along x

  Vector3d origin(std::size_t row) const {
    if (kind != RangeSensorKind::airborne)
      return eye;
    return Vector3d(line_start + (static_cast<double>(row) + 0.5) * line_spacing, eye.y(), eye.z());
  }
  Vector3d direction(std::size_t row, std::size_t col) const {
    const double u = static_cast<double>(col) + 0.5, v = static_cast<double>(row) + 0.5;
    switch (kind) {
      case RangeSensorKind::depth_camera:
        return (rotation * Vector3d((u - cx) / fx, (v - cy) / fx, 1.0)).normalized();
      case RangeSensorKind::lidar: {
        const double azimuth = 2.0 * kPi * u / static_cast<double>(width);
        const double elevation =
            (kLidarTop - (kLidarTop - kLidarBottom) * v / static_cast<double>(height)) * kDegree;
        return Vector3d(std::cos(elevation) * std::cos(azimuth),
                        std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
      }
      case RangeSensorKind::airborne: {
        const double across =
            (-kAirborneHalfSwath + 2.0 * kAirborneHalfSwath * u / static_cast<double>(width)) *
            kDegree;
        return Vector3d(0.0, std::sin(across), -std::cos(across));
      }
    }
    return Vector3d::UnitZ();
  }
};

/// The camera frame looking from \a eye at \a target with z up: columns right, down, forward.
Eigen::Matrix3d lookAt(const Vector3d& eye, const Vector3d& target) {
  const Vector3d forward = (target - eye).normalized();
  const Vector3d right = forward.cross(Vector3d::UnitZ()).normalized();
  Eigen::Matrix3d r;
  r.col(0) = right;
  r.col(1) = forward.cross(right);
  r.col(2) = forward;
  return r;
}

RayGrid rayGrid(const SensorScene& scene, const RangeSensorParameters& p, std::uint64_t seed) {
  std::mt19937_64 rng(seed ^ 0x5EED5CA11EDull);
  auto draw = [&rng](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  RayGrid g;
  g.kind = p.sensor;
  switch (p.sensor) {
    case RangeSensorKind::depth_camera: {
      g.width = p.width.value_or(640);
      g.height = p.height.value_or(480);
      const double azimuth = draw(-50.0, 50.0) * kDegree;
      const double distance = draw(p.distance_min, p.distance_max);
      g.eye = scene.focus +
              Vector3d(distance * std::sin(azimuth), -distance * std::cos(azimuth), draw(0.3, 0.9));
      const Vector3d target = scene.focus + Vector3d(draw(-0.15, 0.15), draw(-0.15, 0.15), 0.0);
      g.rotation = lookAt(g.eye, target);
      g.fx = p.focal * static_cast<double>(g.width) / 640.0;
      g.cx = 0.5 * static_cast<double>(g.width);
      g.cy = 0.5 * static_cast<double>(g.height);
      break;
    }
    case RangeSensorKind::lidar:
      g.width = p.width.value_or(1800);
      g.height = p.height.value_or(350);
      g.eye = scene.focus + Vector3d(draw(-1.0, 1.0), draw(-1.0, 1.0), draw(1.5, 2.0));
      break;
    case RangeSensorKind::airborne: {
      g.width = p.width.value_or(800);
      // One line's footprint at nadir between lines: square cells on the ground.
      g.line_spacing =
          p.altitude * 2.0 * kAirborneHalfSwath * kDegree / static_cast<double>(g.width);
      g.height = p.height.value_or(
          static_cast<std::size_t>(std::ceil(2.0 * scene.extent / g.line_spacing)));
      g.line_start = scene.focus.x() - 0.5 * g.line_spacing * static_cast<double>(g.height);
      g.eye = Vector3d(scene.focus.x(), scene.focus.y() + draw(-5.0, 5.0), p.altitude);
      g.rotation.col(0) = Vector3d::UnitY();
      g.rotation.col(1) = Vector3d::UnitX();
      g.rotation.col(2) = -Vector3d::UnitZ();
      break;
    }
  }
  return g;
}

}  // namespace

void RangeSensorParameters::validate() const {
  validateDeclared(*this, "scan sampling");
  if (distance_max < distance_min)
    throw InvalidParameterError(
        "scan sampling: distance_max = " + parameterNumberText(distance_max) +
        " is below distance_min = " + parameterNumberText(distance_min));
  if (width && height && *width * *height > 100000000)
    throw InvalidParameterError("scan sampling: width × height is above 10^8 cells");
}

RangeScan scanScene(const SensorScene& scene, const RangeSensorParameters& parameters,
                    std::uint64_t seed, int threads) {
  parameters.validate();
  const int workers = resolveThreads(threads);
  const RayGrid grid = rayGrid(scene, parameters, seed);
  if (grid.width * grid.height > 100000000)
    throw InvalidParameterError("scan sampling: width × height is above 10^8 cells");
  const bool camera = parameters.sensor == RangeSensorKind::depth_camera;
  const double range_noise = parameters.range_noise.value_or(
      parameters.sensor == RangeSensorKind::airborne ? 0.02 : 0.005);
  const double far = camera ? kCameraFar
                     : parameters.sensor == RangeSensorKind::lidar
                         ? kLidarFar
                         : std::numeric_limits<double>::infinity();
  const double cos_max = std::cos(parameters.max_incidence);
  const double nan = std::numeric_limits<double>::quiet_NaN();

  RangeScan scan;
  scan.width = grid.width;
  scan.height = grid.height;
  const auto cells = static_cast<Eigen::Index>(grid.width * grid.height);
  scan.points.setConstant(3, cells, nan);
  scan.normals.setConstant(3, cells, nan);
  scan.labels.assign(static_cast<std::size_t>(cells), -1);
  for (const auto& piece : scene.pieces)
    scan.truth.push_back(piece.surface);
  scan.origin = grid.eye;
  scan.orientation = Eigen::Quaterniond(grid.rotation);

  const Vector3d forward = grid.rotation.col(2);
  const auto rows = static_cast<std::ptrdiff_t>(grid.height);
#pragma omp parallel for schedule(dynamic, 4) num_threads(workers)
  for (std::ptrdiff_t row = 0; row < rows; ++row) {
    const auto r = static_cast<std::size_t>(row);
    const Vector3d o = grid.origin(r);
    for (std::size_t c = 0; c < grid.width; ++c) {
      const std::size_t cell = r * grid.width + c;
      const Vector3d d = grid.direction(r, c);
      // The nearest piece along the ray.
      double best = far / (camera ? std::max(d.dot(forward), 1e-9) : 1.0);
      int hit = -1;
      for (std::size_t k = 0; k < scene.pieces.size(); ++k)
        if (const auto t = intersect(scene.pieces[k], o, d, 1e-6, best)) {
          best = *t;
          hit = static_cast<int>(k);
        }
      if (hit < 0)
        continue;
      const Primitive& surface = scene.pieces[static_cast<std::size_t>(hit)].surface;
      const Vector3d exact = o + best * d;
      Vector3d normal = surfaceNormal(exact, surface);
      if (normal.dot(d) > 0.0)
        normal = -normal;
      if (-normal.dot(d) < cos_max)
        continue;  // grazing: no return
      CellRandom random(seed, cell);
      if (parameters.dropout > 0.0 && random.uniform() < parameters.dropout)
        continue;
      double t = best;
      if (camera) {
        // Noise on the depth z, then the depth recorded on disparity levels.
        const double along = d.dot(forward), z = best * along;
        const double sigma =
            parameters.noise_a + parameters.noise_b * std::pow(z - parameters.noise_z0, 2);
        double depth = z + sigma * random.gaussian();
        if (parameters.disparity_step > 0.0) {
          const double fb = grid.fx * parameters.baseline;
          const double level = std::round(fb / depth / parameters.disparity_step);
          if (!(level > 0.0))
            continue;
          depth = fb / (level * parameters.disparity_step);
        }
        // Then stored in whole depth units (OpenNI's and RealSense's millimetres).
        if (parameters.depth_unit > 0.0)
          depth = std::round(depth / parameters.depth_unit) * parameters.depth_unit;
        if (depth < kCameraNear || depth > kCameraFar)
          continue;
        t = depth / along;
      } else {
        t += range_noise * random.gaussian();
      }
      scan.points.col(static_cast<Eigen::Index>(cell)) = o + t * d;
      scan.normals.col(static_cast<Eigen::Index>(cell)) = normal;
      const int continued = scene.pieces[static_cast<std::size_t>(hit)].continues;
      scan.labels[cell] = continued >= 0 ? continued : hit;
    }
  }
  // The truth is what the sensor saw: pieces with too few returns are not truth, and the others
  // are numbered in the order of the scene.
  std::vector<std::size_t> count(scan.truth.size(), 0);
  for (std::int32_t l : scan.labels)
    if (l >= 0)
      ++count[static_cast<std::size_t>(l)];
  std::vector<std::int32_t> renumbered(scan.truth.size(), -1);
  std::vector<Primitive> seen;
  for (std::size_t k = 0; k < scan.truth.size(); ++k)
    if (count[k] >= parameters.truth_min_points) {
      renumbered[k] = static_cast<std::int32_t>(seen.size());
      seen.push_back(scan.truth[k]);
    }
  scan.truth = std::move(seen);
  scan.types.assign(scan.labels.size(), -1);
  for (std::size_t i = 0; i < scan.labels.size(); ++i) {
    std::int32_t& l = scan.labels[i];
    if (l < 0)
      continue;
    ++scan.returns;
    l = renumbered[static_cast<std::size_t>(l)];
    if (l >= 0)
      scan.types[i] = static_cast<std::int32_t>(scan.truth[static_cast<std::size_t>(l)].index());
  }
  if (camera) {
    // A depth camera delivers its frame in its own coordinates (x right, y down, z forward), as
    // PCL's OpenNI grabber does: the points, normals and true primitives move there.
    const Eigen::Matrix3d to_camera = grid.rotation.transpose();
    const Vector3d shift = -(to_camera * grid.eye);
    for (Eigen::Index i = 0; i < scan.points.cols(); ++i)
      if (scan.points.col(i).allFinite()) {
        scan.points.col(i) = to_camera * scan.points.col(i) + shift;
        scan.normals.col(i) = to_camera * scan.normals.col(i);
      }
    for (auto& primitive : scan.truth)
      primitive = transformed(primitive, to_camera, shift);
    scan.origin.setZero();
    scan.orientation.setIdentity();
  }
  return scan;
}

}  // namespace slipfit
