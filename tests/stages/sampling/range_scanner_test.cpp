// The simulated range sensors: returns lie exactly on their true primitive (noise off), nothing
// is seen through an object, the noise is the published model's and lies along the ray, depth is
// on disparity levels, grazing surfaces give no return, and the scan is the same for any thread
// count.
#include "slipfit/sampling/range_scanner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <variant>
#include <vector>

namespace slipfit {
namespace {

RangeSensorParameters noiseless(RangeSensorKind kind) {
  RangeSensorParameters p;
  p.sensor = kind;
  p.noise_a = p.noise_b = 0.0;
  p.disparity_step = 0.0;
  p.range_noise = 0.0;
  p.truth_min_points = 1;
  if (kind == RangeSensorKind::lidar) {  // 0.4° steps: a quarter of the cells, same geometry
    p.width = 900;
    p.height = 175;
  }
  return p;
}

/// The ray of a return from the scan's origin (the camera frame's origin for a depth camera;
/// airborne rays start on the flight line, handled by the callers).
Eigen::Vector3d rayOf(const RangeScan& scan, Eigen::Index i) {
  return (scan.points.col(i) - scan.origin).normalized();
}

struct Case {
  RangeSensorKind sensor;
  SensorSetting setting;
};

class EverySensor : public ::testing::TestWithParam<Case> {};

// Noise off, every return lies on its true primitive. The quadrics' roots come from the
// quadratic formula in its stable form (relative error ~1e-15 of the range) and the torus's from
// sphere tracing to 1e-9 of its size (≤ 1 m): 1e-8 m bounds both at ranges up to 150 m. Every
// return faces the ray within max_incidence.
TEST_P(EverySensor, ReturnsLieOnTheirTruePrimitiveWithinTheIncidenceLimit) {
  const Case c = GetParam();
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const RangeSensorParameters p = noiseless(c.sensor);
    const RangeScan scan = scanScene(sensorScene(c.setting, seed), p, seed);
    ASSERT_EQ(scan.points.cols(), static_cast<Eigen::Index>(scan.width * scan.height));
    ASSERT_GT(scan.returns, scan.width * scan.height / 5) << "seed " << seed;
    std::size_t checked = 0;
    for (Eigen::Index i = 0; i < scan.points.cols(); ++i) {
      if (!scan.points.col(i).allFinite()) {
        EXPECT_EQ(scan.labels[static_cast<std::size_t>(i)], -1);
        continue;
      }
      const std::int32_t label = scan.labels[static_cast<std::size_t>(i)];
      ASSERT_GE(label, 0);
      const Primitive& truth = scan.truth[static_cast<std::size_t>(label)];
      EXPECT_LT(distance(scan.points.col(i), truth), 1e-8) << "seed " << seed << " cell " << i;
      EXPECT_EQ(scan.types[static_cast<std::size_t>(i)], static_cast<int>(truth.index()));
      if (c.sensor != RangeSensorKind::airborne) {
        const double cos_incidence = -scan.normals.col(i).dot(rayOf(scan, i));
        EXPECT_GE(cos_incidence, std::cos(p.max_incidence) - 1e-12) << "cell " << i;
      }
      ++checked;
    }
    EXPECT_EQ(checked, scan.returns);
  }
}

INSTANTIATE_TEST_SUITE_P(
    RangeScanner, EverySensor,
    ::testing::Values(Case{RangeSensorKind::depth_camera, SensorSetting::tabletop},
                      Case{RangeSensorKind::lidar, SensorSetting::yard},
                      Case{RangeSensorKind::airborne, SensorSetting::yard},
                      Case{RangeSensorKind::depth_camera, SensorSetting::yard}));

// A ball in front of a wall: no wall return is seen through the ball (its ray passes the ball's
// centre closer than the radius), and every ball return is on the half facing the camera.
/// The corners of a polygonal piece (parallelogram, triangle); none for the others.
std::vector<Eigen::Vector3d> cornersOf(const SurfacePiece& piece) {
  const Eigen::Vector3d& c = piece.corner;
  if (piece.bounds == PieceBounds::parallelogram)
    return {c, c + piece.edge_u, c + piece.edge_u + piece.edge_v, c + piece.edge_v};
  if (piece.bounds == PieceBounds::triangle)
    return {c, c + piece.edge_u, c + piece.edge_v};
  return {};
}

/// Whether a corner of one polygon lies on an edge of the other (within 1e-9).
bool shareAnEdgePoint(const std::vector<Eigen::Vector3d>& a,
                      const std::vector<Eigen::Vector3d>& b) {
  for (int pass = 0; pass < 2; ++pass) {
    const auto& corners = pass == 0 ? a : b;
    const auto& polygon = pass == 0 ? b : a;
    for (const auto& p : corners)
      for (std::size_t e = 0; e < polygon.size(); ++e) {
        const Eigen::Vector3d& s = polygon[e];
        const Eigen::Vector3d edge = polygon[(e + 1) % polygon.size()] - s;
        const double t = std::clamp((p - s).dot(edge) / edge.squaredNorm(), 0.0, 1.0);
        if ((s + t * edge - p).norm() < 1e-9)
          return true;
      }
  }
  return false;
}

// One surface is one true segment: where a scene builds a plane from two touching pieces (a
// house's gable over its end wall), the second continues the first, and no two true planes
// coincide where they touch — a segmentation that joins them is right, and the score must say so.
// (Coplanar pieces apart, as the faces of two table legs in a row, are two segments.)
TEST(SensorScene, TouchingPiecesOfOnePlaneAreOneTrueSurface) {
  std::size_t joined = 0;
  for (SensorSetting setting : {SensorSetting::tabletop, SensorSetting::yard})
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
      const SensorScene scene = sensorScene(setting, seed);
      std::vector<std::size_t> planes;
      for (std::size_t k = 0; k < scene.pieces.size(); ++k) {
        const SurfacePiece& piece = scene.pieces[k];
        if (piece.continues >= 0) {
          ASSERT_LT(piece.continues, static_cast<int>(k));
          const auto& base = scene.pieces[static_cast<std::size_t>(piece.continues)];
          const auto& own = std::get<Plane>(piece.surface);
          const auto& under = std::get<Plane>(base.surface);
          const double sign = own.normal.dot(under.normal) > 0 ? 1.0 : -1.0;
          EXPECT_NEAR(std::abs(own.normal.dot(under.normal)), 1.0, 1e-12);
          EXPECT_NEAR(own.d, sign * under.d, 1e-9);
          EXPECT_TRUE(shareAnEdgePoint(cornersOf(piece), cornersOf(base)));
          ++joined;
        } else if (std::holds_alternative<Plane>(piece.surface)) {
          planes.push_back(k);
        }
      }
      for (std::size_t i = 0; i < planes.size(); ++i)
        for (std::size_t j = i + 1; j < planes.size(); ++j) {
          const auto& a = scene.pieces[planes[i]];
          const auto& b = scene.pieces[planes[j]];
          const auto& pa = std::get<Plane>(a.surface);
          const auto& pb = std::get<Plane>(b.surface);
          const double cosine = pa.normal.dot(pb.normal);
          const double sign = cosine > 0 ? 1.0 : -1.0;
          const bool coplanar = std::abs(cosine) > 1 - 1e-12 && std::abs(pa.d - sign * pb.d) < 1e-9;
          EXPECT_FALSE(coplanar && shareAnEdgePoint(cornersOf(a), cornersOf(b)))
              << "seed " << seed << ": pieces " << planes[i] << " and " << planes[j]
              << " are one plane and touch";
        }
    }
  EXPECT_GT(joined, 0u);  // the yard's houses have gables
}

TEST(RangeScanner, NothingIsSeenThroughAnObject) {
  SensorScene scene;
  scene.pieces.push_back(parallelogram(Eigen::Vector3d(-3, 2, -1), Eigen::Vector3d(6, 0, 0),
                                       Eigen::Vector3d(0, 0, 4)));
  scene.pieces.push_back(sphereCap(Eigen::Vector3d(0, 0.5, 0.5), 0.3, Eigen::Vector3d::UnitZ()));
  scene.focus = Eigen::Vector3d(0, 0.5, 0.2);
  const RangeScan scan = scanScene(scene, noiseless(RangeSensorKind::depth_camera), 4);
  const auto& ball = std::get<Sphere>(scan.truth[1]);
  std::size_t wall = 0, on_ball = 0;
  for (Eigen::Index i = 0; i < scan.points.cols(); ++i) {
    if (!scan.points.col(i).allFinite())
      continue;
    const Eigen::Vector3d ray = rayOf(scan, i);
    if (scan.labels[static_cast<std::size_t>(i)] == 0) {
      ++wall;
      const Eigen::Vector3d w = ball.center - scan.origin;
      const double miss = (w - w.dot(ray) * ray).norm();
      EXPECT_GT(miss, ball.radius * (1 - 1e-9)) << "a wall return behind the ball, cell " << i;
    } else {
      ++on_ball;
      EXPECT_LE((scan.points.col(i) - ball.center).dot(ray), 1e-9);
    }
  }
  EXPECT_GT(wall, 10000u);
  EXPECT_GT(on_ball, 1000u);
}

/// The sample \a e is standard normal: its mean within 5 standard errors (1/√N) of 0 and its
/// variance within 5 standard errors (√(2/N)) of 1.
void expectStandardNormal(const std::vector<double>& e) {
  double mean = 0.0, var = 0.0;
  for (double x : e)
    mean += x;
  mean /= static_cast<double>(e.size());
  for (double x : e)
    var += (x - mean) * (x - mean);
  var /= static_cast<double>(e.size() - 1);
  const double n = static_cast<double>(e.size());
  EXPECT_NEAR(mean, 0.0, 5.0 / std::sqrt(n));
  EXPECT_NEAR(var, 1.0, 5.0 * std::sqrt(2.0 / n));
}

/// Calls \a f(cell, plane, ray) for every return on a true plane.
template <typename F>
void forEachPlaneReturn(const RangeScan& scan, F&& f) {
  for (Eigen::Index i = 0; i < scan.points.cols(); ++i) {
    const std::int32_t label = scan.labels[static_cast<std::size_t>(i)];
    if (label >= 0)
      if (const auto* plane = std::get_if<Plane>(&scan.truth[static_cast<std::size_t>(label)]))
        f(i, *plane, rayOf(scan, i));
  }
}

/// The depth error of each camera return over the σ(z) of the model, against the depth of its
/// ray's exact intersection with its true plane; only planes are used (their intersection is
/// closed-form here, independently of the scanner).
std::vector<double> normalisedDepthErrors(const RangeScan& scan, const RangeSensorParameters& p) {
  std::vector<double> e;
  forEachPlaneReturn(scan, [&](Eigen::Index i, const Plane& plane, const Eigen::Vector3d& ray) {
    const double z_true = plane.d / plane.normal.dot(ray) * ray.z();
    const double sigma = p.noise_a + p.noise_b * std::pow(z_true - p.noise_z0, 2);
    e.push_back((scan.points(2, i) - z_true) / sigma);
  });
  return e;
}

// With the levels off, the depth error over σ(z) = a + b (z − z0)² is standard normal: its mean
// within 5 standard errors of 0, its variance within 5 standard errors (√(2/N)) of 1. The error
// is along the ray: the point stays on its pixel's ray.
TEST(RangeScanner, DepthNoiseIsTheKinectModelAlongTheRay) {
  RangeSensorParameters p;
  p.disparity_step = 0.0;
  std::vector<double> e;
  for (std::uint64_t seed : {5u, 6u}) {
    const RangeScan scan = scanScene(sensorScene(SensorSetting::tabletop, seed), p, seed);
    const auto part = normalisedDepthErrors(scan, p);
    e.insert(e.end(), part.begin(), part.end());
  }
  ASSERT_GT(e.size(), 100000u);
  expectStandardNormal(e);
}

// With the levels on, every depth is f B / (k · step) for an integer k (relative 1e-9), and
// neighbouring levels at 1 m lie z² step / (f B) = 3.2 mm apart.
TEST(RangeScanner, DepthIsRecordedOnDisparityLevels) {
  const RangeSensorParameters p;
  const RangeScan scan = scanScene(sensorScene(SensorSetting::tabletop, 7), p, 7);
  const double fb = p.focal * p.baseline;
  std::size_t checked = 0;
  for (Eigen::Index i = 0; i < scan.points.cols(); ++i) {
    if (!scan.points.col(i).allFinite())
      continue;
    const double k = fb / (scan.points(2, i) * p.disparity_step);
    EXPECT_NEAR(k, std::round(k), 1e-9 * k) << "cell " << i;
    ++checked;
  }
  EXPECT_GT(checked, 100000u);
  EXPECT_NEAR(p.disparity_step / fb, 0.0032, 0.0001);
}

// A terrestrial LiDAR's range error along the ray over range_noise is standard normal (bounds as
// above), on the yard's ground, walls and roofs.
TEST(RangeScanner, LidarRangeNoiseIsGaussianAlongTheRay) {
  RangeSensorParameters p;
  p.sensor = RangeSensorKind::lidar;
  p.range_noise = 0.004;
  const RangeScan scan = scanScene(sensorScene(SensorSetting::yard, 8), p, 8);
  std::vector<double> e;
  forEachPlaneReturn(scan, [&](Eigen::Index i, const Plane& plane, const Eigen::Vector3d& ray) {
    const double t_true = (plane.d - plane.normal.dot(scan.origin)) / plane.normal.dot(ray);
    e.push_back(((scan.points.col(i) - scan.origin).norm() - t_true) / *p.range_noise);
  });
  ASSERT_GT(e.size(), 50000u);
  expectStandardNormal(e);
}

// The same scan for 1 and 2 threads (each cell has its own random stream); another seed gives
// another scene.
TEST(RangeScanner, TheScanIsTheSameForAnyThreadCount) {
  RangeSensorParameters p;
  p.dropout = 0.05;
  const SensorScene scene = sensorScene(SensorSetting::tabletop, 9);
  const RangeScan a = scanScene(scene, p, 9, 1), b = scanScene(scene, p, 9, 2);
  ASSERT_EQ(a.points.size(), b.points.size());
  EXPECT_EQ(std::memcmp(a.points.data(), b.points.data(), sizeof(double) * a.points.size()), 0);
  EXPECT_EQ(a.labels, b.labels);
  const RangeScan c = scanScene(sensorScene(SensorSetting::tabletop, 10), p, 10, 1);
  EXPECT_NE(a.labels, c.labels);
}

TEST(RangeScanner, ParametersOutOfRangeAreRefusedByName) {
  RangeSensorParameters p;
  p.distance_min = 3.0;
  p.distance_max = 2.0;
  EXPECT_THROW(p.validate(), InvalidParameterError);
  p = RangeSensorParameters{};
  p.max_incidence = 95.0 * kDegree;
  try {
    p.validate();
    FAIL() << "max_incidence 95° accepted";
  } catch (const InvalidParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("max_incidence"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace slipfit
