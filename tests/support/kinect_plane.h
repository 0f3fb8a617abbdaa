#pragma once
/// \file A Kinect-like depth image of a tilted plane, shared by the depth-quantization and
/// segmentation tests.

#include <Eigen/Core>

#include <cmath>
#include <random>
#include <vector>

namespace slipfit::testing {

/// A Kinect's depth step: about 3 mm at 1 m (levels c·z² apart).
constexpr double kStepPerZ2 = 0.003;
/// The plane's tilt about x.
constexpr double kKinectPlaneTilt = 40.0 * 3.14159265358979323846 / 180.0;

/// The unit normal of the plane kinectPlane samples, z = 1.5 + tan(tilt)·y.
inline Eigen::Vector3d kinectPlaneNormal() {
  return Eigen::Vector3d(0.0, -std::sin(kKinectPlaneTilt), std::cos(kKinectPlaneTilt));
}

/// A pixel grid (focal length 525, 320 × 240) seeing a plane tilted 40° about x at depth 1–2 m,
/// with Gaussian depth noise \a sigma, its depth then recorded as a disparity sensor does (with
/// \a quantize): the nearest of the levels 1/(c d), d an integer, c = kStepPerZ2, which lie c·z²
/// apart. \a bend (optional) is added to the depth before the noise: a sensor's distortion.
template <typename Bend>
Eigen::Matrix3Xd kinectPlane(double sigma, bool quantize, unsigned seed, Bend bend) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<Eigen::Vector3d> pts;
  for (int v = 0; v < 240; ++v)
    for (int u = 0; u < 320; ++u) {
      const Eigen::Vector3d ray((u - 160) / 525.0, (v - 120) / 525.0, 1.0);
      // plane: z = 1.5 + tan(tilt)·y  →  ray·t
      const double t = 1.5 / (1.0 - std::tan(kKinectPlaneTilt) * ray.y());
      double z = t + bend(t) + noise(rng);
      if (quantize)  // depth from an integer disparity d ∝ 1/z: levels 1/(c d), c z² apart
        z = 1.0 / (kStepPerZ2 * std::round(1.0 / (kStepPerZ2 * z)));
      pts.emplace_back(ray.x() * z, ray.y() * z, z);
    }
  Eigen::Matrix3Xd m(3, static_cast<Eigen::Index>(pts.size()));
  for (std::size_t i = 0; i < pts.size(); ++i)
    m.col(static_cast<Eigen::Index>(i)) = pts[i];
  return m;
}

inline Eigen::Matrix3Xd kinectPlane(double sigma, bool quantize, unsigned seed) {
  return kinectPlane(sigma, quantize, seed, [](double) { return 0.0; });
}

}  // namespace slipfit::testing
