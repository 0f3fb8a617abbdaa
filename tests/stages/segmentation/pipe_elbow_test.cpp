// Pipes with elbows: straight runs (cylinders) joined tangent-continuously by quarter tori of the
// same tube radius — the joint where normal-continuity growth leaks. Every elbow must come out as
// a torus segment, every run as a cylinder (the issue's "every torus in a scene of pipes with
// elbows is found as a torus").

#include "segment_cloud.h"

#include "slipfit/core/angle_units.h"
#include "slipfit/sampling/primitive_sampler.h"
#include "slipfit/segmentation/segmentation_metrics.h"

#include <gtest/gtest.h>
#include <pcl/point_types.h>

#include <Eigen/Geometry>

#include <cmath>
#include <iostream>

namespace slipfit {
namespace {

struct Piece {
  PrimitiveSamplingParameters sampling;
  PrimitiveType type;
};

/// An L-shaped pipe of tube radius r bending with major radius R between two runs of length L,
/// rotated by \a rotation and moved to \a offset. Point counts proportional to area (density
/// \a per_area), noise sigma.
std::vector<Piece> lPipe(double r, double R, double L, const Eigen::Matrix3d& rotation,
                         const Eigen::Vector3d& offset, double per_area, double sigma,
                         std::uint64_t seed) {
  const Eigen::Vector3d a = rotation * Eigen::Vector3d::UnitZ();
  // The sampler's frame around a torus axis: β = 0 along u, β = π/2 along v.
  const Eigen::Vector3d u = a.unitOrthogonal(), v = a.cross(u);
  const Eigen::Vector3d c = offset;
  std::vector<Piece> pieces(3);
  // The elbow: β in [0, π/2], from c + R u (tangent +v) to c + R v (tangent −u).
  pieces[0].sampling.primitive = Torus{a, c, R, r};
  pieces[0].sampling.angle_min = 0.0;
  pieces[0].sampling.angle_max = kPi / 2;
  pieces[0].sampling.points = static_cast<std::size_t>(per_area * kPi / 2 * R * 2 * kPi * r);
  pieces[0].type = PrimitiveType::torus;
  // The run into it, along v, ending at c + R u; the run out of it, along −u, from c + R v.
  pieces[1].sampling.primitive = Cylinder{-v, c + R * u, r};  // back from the elbow
  pieces[1].sampling.extent_min = 0.0;
  pieces[1].sampling.extent = L;
  pieces[2].sampling.primitive = Cylinder{-u, c + R * v, r};
  pieces[2].sampling.extent_min = 0.0;
  pieces[2].sampling.extent = L;
  for (int k = 1; k < 3; ++k) {
    pieces[static_cast<std::size_t>(k)].sampling.points =
        static_cast<std::size_t>(per_area * 2 * kPi * r * L);
    pieces[static_cast<std::size_t>(k)].type = PrimitiveType::cylinder;
  }
  for (std::size_t k = 0; k < 3; ++k) {
    pieces[k].sampling.noise = sigma;
    pieces[k].sampling.seed = seed + k;
  }
  return pieces;
}

TEST(PipeElbows, EveryElbowIsATorusAndEveryRunACylinder) {
  std::vector<Piece> pieces;
  const double per_area = 4000.0;  // points per unit area: spacing ≈ 0.016
  const struct {
    double r, R, L;
    Eigen::Vector3d axis;
    double angle;
    Eigen::Vector3d offset;
  } pipes[] = {
      {0.10, 0.30, 1.0, Eigen::Vector3d::UnitZ(), 0.0, Eigen::Vector3d(0, 0, 0)},
      {0.15, 0.50, 1.2, Eigen::Vector3d(1, 1, 0).normalized(), 0.7, Eigen::Vector3d(3, 0, 0)},
      {0.08, 0.20, 0.8, Eigen::Vector3d(0, 1, 2).normalized(), 2.1, Eigen::Vector3d(0, 3, 1)},
      {0.20, 0.40, 1.5, Eigen::Vector3d(1, 0, 1).normalized(), 4.0, Eigen::Vector3d(3, 3, -1)},
  };
  std::uint64_t seed = 100;
  for (const auto& p : pipes) {
    const Eigen::Matrix3d rotation = Eigen::AngleAxisd(p.angle, p.axis).toRotationMatrix();
    for (Piece& piece : lPipe(p.r, p.R, p.L, rotation, p.offset, per_area, 0.002, seed))
      pieces.push_back(std::move(piece));
    seed += 10;
  }
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  std::vector<std::int32_t> truth;
  std::vector<int> truth_types;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    Eigen::Matrix3Xd x, n;
    samplePrimitive(pieces[k].sampling, x, n);
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
      pcl::PointNormal q;
      q.getVector3fMap() = x.col(i).cast<float>();
      cloud->push_back(q);
      truth.push_back(static_cast<std::int32_t>(k));
    }
    truth_types.push_back(static_cast<int>(pieces[k].type));
  }
  const SegmentationResult r = testing::segmentCloud(cloud, 12).result;
  std::vector<int> predicted_types;
  for (const auto& s : r.segments)
    predicted_types.push_back(static_cast<int>(s.fit.type));
  const SegmentationScore score = scoreSegmentation(truth, r.labels, truth_types, predicted_types);
  std::cout << cloud->size() << " points, " << r.segments.size() << " segments (truth "
            << pieces.size() << "), mean IoU " << score.mean_iou << ", type accuracy "
            << score.type_accuracy << "\n";
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const int m = score.match[k];
    std::cout << "  " << primitiveTypeName(pieces[k].type) << ": IoU " << score.iou[k] << " as "
              << (m >= 0 ? primitiveTypeName(r.segments[static_cast<std::size_t>(m)].fit.type)
                         : "nothing")
              << "\n";
    ASSERT_GE(m, 0) << "piece " << k;
    EXPECT_EQ(r.segments[static_cast<std::size_t>(m)].fit.type, pieces[k].type) << "piece " << k;
    // Measured (4 L-pipes, σ = 0.002, tube radii 0.08–0.2): elbows 0.67–0.81, runs 0.83–0.95.
    // Where a run meets its elbow tangentially the two surfaces stay within the tolerance of each
    // other for about √(2Rε) beyond the joint, and the elbow's torus takes the runs' first rows
    // there (it holds 99 % of its own points; 10–30 % of its segment are run points).
    EXPECT_GE(score.iou[k], pieces[k].type == PrimitiveType::torus ? 0.65 : 0.8) << "piece " << k;
  }
}

}  // namespace
}  // namespace slipfit
