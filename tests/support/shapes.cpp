#include "shapes.h"

#include "slipfit/core/angle_units.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace slipfit::testing {

namespace {

pcl::PointNormal make(const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
  pcl::PointNormal q;
  q.getVector3fMap() = p.cast<float>();
  q.getNormalVector3fMap() = n.normalized().cast<float>();
  q.curvature = 0.0f;
  return q;
}

void finish(Cloud& c) {
  c.width = static_cast<std::uint32_t>(c.size());
  c.height = 1;
  c.is_dense = true;
}
}  // namespace

Cloud sampleSphere(std::size_t n, const Eigen::Vector3f& center, float radius, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), phi(0.0, 2.0 * kPi);
  Cloud c;
  c.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double z = u(rng), a = phi(rng), s = std::sqrt(std::max(0.0, 1.0 - z * z));
    const Eigen::Vector3d d(s * std::cos(a), s * std::sin(a), z);
    c.push_back(make(center.cast<double>() + radius * d, d));
  }
  finish(c);
  return c;
}

Cloud sampleCylinder(std::size_t n, const Eigen::Vector3f& base, float radius, float height,
                     std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> h(0.0, height), phi(0.0, 2.0 * kPi);
  Cloud c;
  c.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double a = phi(rng);
    const Eigen::Vector3d d(std::cos(a), std::sin(a), 0.0);
    c.push_back(make(base.cast<double>() + radius * d + Eigen::Vector3d(0, 0, h(rng)), d));
  }
  finish(c);
  return c;
}

Cloud sampleTorus(std::size_t n, const Eigen::Vector3f& center, float R, float r,
                  std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ang(0.0, 2.0 * kPi), acc(0.0, 1.0);
  Cloud c;
  c.reserve(n);
  while (c.size() < n) {
    const double alpha = ang(rng), beta = ang(rng);
    // Rejection on the area element r(R + r cos α) keeps the sampling area-uniform.
    if (acc(rng) * (R + r) > R + r * std::cos(alpha))
      continue;
    const Eigen::Vector3d nrm(std::cos(alpha) * std::cos(beta), std::cos(alpha) * std::sin(beta),
                              std::sin(alpha));
    const Eigen::Vector3d p((R + r * std::cos(alpha)) * std::cos(beta),
                            (R + r * std::cos(alpha)) * std::sin(beta), r * std::sin(alpha));
    c.push_back(make(center.cast<double>() + p, nrm));
  }
  finish(c);
  return c;
}

Cloud samplePlane(std::size_t n, float x0, float x1, float y0, float y1, float z,
                  std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ux(x0, x1), uy(y0, y1);
  Cloud c;
  c.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = ux(rng);
    c.push_back(make(Eigen::Vector3d(x, uy(rng), z), Eigen::Vector3d::UnitZ()));
  }
  finish(c);
  return c;
}

void addNoise(Cloud& cloud, float sigma, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> g(0.0f, sigma);
  for (auto& p : cloud.points) {
    p.x += g(rng);
    p.y += g(rng);
    p.z += g(rng);
  }
}

void append(Cloud& a, const Cloud& b) {
  a.insert(a.end(), b.begin(), b.end());
  finish(a);
}

Cloud millionPointScene() {
  Cloud c = samplePlane(500000, -3, 3, -3, 3, 0, 1);
  append(c, sampleSphere(250000, Eigen::Vector3f(-1, 1, 1), 0.8f, 2));
  append(c, sampleTorus(250000, Eigen::Vector3f(1.2f, -1, 0.6f), 1.0f, 0.3f, 3));
  addNoise(c, 0.006f, 4);
  for (auto& p : c.points)
    p.getNormalVector3fMap().setConstant(std::numeric_limits<float>::quiet_NaN());
  return c;
}

double maxAngleDeg(const Eigen::Matrix3Xf& normals, const Eigen::Matrix3Xf& reference,
                   bool unsigned_) {
  double worst = 0.0;
  for (Eigen::Index i = 0; i < normals.cols(); ++i) {
    double c = normals.col(i).cast<double>().normalized().dot(
        reference.col(i).cast<double>().normalized());
    if (unsigned_)
      c = std::abs(c);
    worst = std::max(worst, std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / kPi);
  }
  return worst;
}

}  // namespace slipfit::testing
