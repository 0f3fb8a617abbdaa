#include "slipfit/sampling/scene_sampler.h"

#include "slipfit/core/angle_units.h"
#include "slipfit/core/exceptions.h"
#include "slipfit/sampling/random_vector.h"

#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <string>

namespace slipfit {

namespace {

// The layout, in units of the object size. The box is turned 30° about z so that no face is
// axis-aligned.
const Eigen::Vector3d kBoxCentre(-1.0, -1.0, 0.0);
constexpr double kBoxHalf = 0.4, kBoxHeight = 0.6, kBoxTurn = kPi / 6;
const Eigen::Vector3d kCylinderBase(1.0, -1.0, 0.0);
constexpr double kCylinderRadius = 0.35, kCylinderHeight = 0.9;
const Eigen::Vector3d kSphereCentre(-1.0, 1.0, 0.45);
constexpr double kSphereRadius = 0.45;
const Eigen::Vector3d kConeApex(1.0, 1.0, 1.0);
constexpr double kConeBase = 0.45;  // radius at z = 0
constexpr double kGroundHalf = 2.0;

Eigen::Vector3d boxAxis(int i) {  // 0: u, 1: v (the turned x and y)
  const double a = kBoxTurn + (i == 0 ? 0.0 : kPi / 2);
  return {std::cos(a), std::sin(a), 0.0};
}

bool onGround(double x, double y) {
  const Eigen::Vector3d d(x - kBoxCentre.x(), y - kBoxCentre.y(), 0.0);
  if (std::abs(d.dot(boxAxis(0))) < kBoxHalf && std::abs(d.dot(boxAxis(1))) < kBoxHalf)
    return false;
  if (std::hypot(x - kCylinderBase.x(), y - kCylinderBase.y()) < kCylinderRadius)
    return false;
  return std::hypot(x - kConeApex.x(), y - kConeApex.y()) >= kConeBase;
}

std::vector<ScenePrimitive> makePrimitives() {
  std::vector<ScenePrimitive> p;
  p.push_back({Plane{Eigen::Vector3d::UnitZ(), 0.0}, "ground"});
  p.push_back({Plane{Eigen::Vector3d::UnitZ(), kBoxHeight}, "box top"});
  for (int axis = 0; axis < 2; ++axis)
    for (double sign : {1.0, -1.0}) {
      const Eigen::Vector3d n = sign * boxAxis(axis);
      p.push_back({Plane{n, n.dot(kBoxCentre) + kBoxHalf}, "box side"});
    }
  p.push_back({Cylinder{Eigen::Vector3d::UnitZ(), kCylinderBase, kCylinderRadius}, "cylinder"});
  p.push_back({Plane{Eigen::Vector3d::UnitZ(), kCylinderHeight}, "cylinder top"});
  p.push_back({Sphere{kSphereCentre, kSphereRadius}, "sphere"});
  p.push_back(
      {Cone{-Eigen::Vector3d::UnitZ(), kConeApex, std::atan(kConeBase / kConeApex.z())}, "cone"});
  return p;
}

}  // namespace

void SceneSamplingParameters::validate() const {
  if (points < 100)
    throw InvalidParameterError("scene sampling: points must be at least 100");
  if (!(noise >= 0.0 && noise <= 0.1))
    throw InvalidParameterError("scene sampling: noise must be in [0, 0.1]");
  if (!(outlier_fraction >= 0.0 && outlier_fraction <= 1.0))
    throw InvalidParameterError("scene sampling: outlier_fraction must be in [0, 1]");
}

const std::vector<ScenePrimitive>& scenePrimitives() {
  static const std::vector<ScenePrimitive> primitives = makePrimitives();
  return primitives;
}

void sampleScene(const SceneSamplingParameters& parameters, Eigen::Matrix3Xd& points,
                 Eigen::Matrix3Xd& normals, std::vector<std::int32_t>& labels) {
  parameters.validate();
  std::mt19937_64 rng(parameters.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);

  const double cone_slant = std::hypot(kConeBase, kConeApex.z());
  const double box_side = 2 * kBoxHalf * kBoxHeight;
  const double ground = 4 * kGroundHalf * kGroundHalf - 4 * kBoxHalf * kBoxHalf -
                        kPi * kCylinderRadius * kCylinderRadius - kPi * kConeBase * kConeBase;
  // Areas in label order (see makePrimitives).
  const double areas[] = {ground,
                          4 * kBoxHalf * kBoxHalf,
                          box_side,
                          box_side,
                          box_side,
                          box_side,
                          2 * kPi * kCylinderRadius * kCylinderHeight,
                          kPi * kCylinderRadius * kCylinderRadius,
                          4 * kPi * kSphereRadius * kSphereRadius,
                          kPi * kConeBase * cone_slant};
  double total = 0.0;
  for (double a : areas)
    total += a;
  const auto outliers = static_cast<std::size_t>(
      std::llround(parameters.outlier_fraction * static_cast<double>(parameters.points)));
  const std::size_t n = parameters.points + outliers;
  points.resize(3, static_cast<Eigen::Index>(n));
  normals.resize(3, static_cast<Eigen::Index>(n));
  labels.assign(n, -1);

  const auto& truth = scenePrimitives();
  std::size_t at = 0;
  double cumulative = 0.0;
  for (int label = 0; label < 10; ++label) {
    cumulative += areas[label];
    // Cumulative rounding: the counts add up to exactly `points`.
    const auto end = label == 9 ? parameters.points
                                : static_cast<std::size_t>(std::llround(
                                      cumulative / total * static_cast<double>(parameters.points)));
    for (; at < end; ++at) {
      Eigen::Vector3d x;
      const double s = unit(rng), t = unit(rng);
      switch (label) {
        case 0: {  // rejection inside the ground square
          double gx = (2 * s - 1) * kGroundHalf, gy = (2 * t - 1) * kGroundHalf;
          while (!onGround(gx, gy)) {
            gx = (2 * unit(rng) - 1) * kGroundHalf;
            gy = (2 * unit(rng) - 1) * kGroundHalf;
          }
          x = {gx, gy, 0.0};
          break;
        }
        case 1:
          x = kBoxCentre + (2 * s - 1) * kBoxHalf * boxAxis(0) +
              (2 * t - 1) * kBoxHalf * boxAxis(1) + kBoxHeight * Eigen::Vector3d::UnitZ();
          break;
        case 2:
        case 3:
        case 4:
        case 5: {
          const int axis = (label - 2) / 2;
          const double sign = (label - 2) % 2 == 0 ? 1.0 : -1.0;
          x = kBoxCentre + sign * kBoxHalf * boxAxis(axis) +
              (2 * s - 1) * kBoxHalf * boxAxis(1 - axis) +
              t * kBoxHeight * Eigen::Vector3d::UnitZ();
          break;
        }
        case 6: {
          const double a = 2 * kPi * s;
          x = kCylinderBase + Eigen::Vector3d(kCylinderRadius * std::cos(a),
                                              kCylinderRadius * std::sin(a), kCylinderHeight * t);
          break;
        }
        case 7: {  // area-uniform disk: radius ∝ √u
          const double a = 2 * kPi * s, r = kCylinderRadius * std::sqrt(t);
          x = kCylinderBase + Eigen::Vector3d(r * std::cos(a), r * std::sin(a), kCylinderHeight);
          break;
        }
        case 8: {  // area-uniform sphere: z uniform (Archimedes)
          const double z = 2 * t - 1, a = 2 * kPi * s, r = std::sqrt(std::max(0.0, 1 - z * z));
          x = kSphereCentre + kSphereRadius * Eigen::Vector3d(r * std::cos(a), r * std::sin(a), z);
          break;
        }
        default: {  // cone side: the area element grows with the distance from the apex
          const double a = 2 * kPi * s, h = std::sqrt(t);  // h: fraction of the way to the base
          x = kConeApex + Eigen::Vector3d(h * kConeBase * std::cos(a), h * kConeBase * std::sin(a),
                                          -h * kConeApex.z());
          break;
        }
      }
      const auto col = static_cast<Eigen::Index>(at);
      normals.col(col) = surfaceNormal(x, truth[static_cast<std::size_t>(label)].primitive);
      if (parameters.noise > 0.0)
        x += parameters.noise * randomVector<3>(gauss, rng);
      points.col(col) = x;
      labels[at] = label;
    }
  }
  for (; at < n; ++at) {
    const auto col = static_cast<Eigen::Index>(at);
    points.col(col) << (2 * unit(rng) - 1) * kGroundHalf, (2 * unit(rng) - 1) * kGroundHalf,
        1.2 * unit(rng);
    Eigen::Vector3d d = randomVector<3>(gauss, rng);
    normals.col(col) = d.normalized();
  }
}

}  // namespace slipfit
