#include "varied_shapes.h"

#include "slipfit/core/angle_units.h"
#include "slipfit/neighborhoods/normal_estimation.h"
#include "slipfit/sampling/motion_surface_sampler.h"
#include "slipfit/sampling/primitive_sampler.h"
#include "slipfit/sampling/random_vector.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <sstream>

namespace slipfit::testing {

namespace {

constexpr Eigen::Index kPoints = 4000;

enum class Sampling { uniform, gradient, scan_lines };

/// Keeps kPoints of the over-sampled cloud: all alike, with a density falling tenfold along a
/// random direction, or on parallel stripes a fifth of their spacing wide (a line scanner).
void thin(Sampling sampling, std::mt19937_64& rng, Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& n) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), unit(0.0, 1.0);
  const Eigen::Vector3d d = randomVector<3>(u, rng).normalized();
  const Eigen::VectorXd along = d.transpose() * x;
  const double lo = along.minCoeff(), span = std::max(along.maxCoeff() - lo, 1e-300);
  Eigen::Index kept = 0;
  for (Eigen::Index i = 0; i < x.cols() && kept < kPoints; ++i) {
    const double t = (along[i] - lo) / span;
    bool keep = true;
    if (sampling == Sampling::gradient)
      keep = unit(rng) < 0.1 + 0.9 * t;
    else if (sampling == Sampling::scan_lines)
      keep = std::fmod(t * 20.0, 1.0) < 0.2;
    if (keep) {
      x.col(kept) = x.col(i);
      n.col(kept) = n.col(i);
      ++kept;
    }
  }
  x.conservativeResize(3, kept);
  n.conservativeResize(3, kept);
}

}  // namespace

void estimatePcaNormals(const Eigen::Matrix3Xd& x, int k, Eigen::Matrix3Xd& n) {
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  const Eigen::Vector3d c = x.rowwise().mean();
  for (Eigen::Index j = 0; j < x.cols(); ++j) {
    pcl::PointXYZ q;
    q.getVector3fMap() = (x.col(j) - c).cast<float>();
    cloud->push_back(q);
  }
  OrientedNormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
  NormalParameters np;
  np.k = k;
  np.threads = 1;
  ne.setParameters(np);
  ne.setInputCloud(cloud);
  pcl::PointCloud<pcl::Normal> normals;
  ne.compute(normals);
  for (Eigen::Index j = 0; j < x.cols(); ++j)
    n.col(j) = normals[static_cast<std::size_t>(j)].getNormalVector3fMap().cast<double>();
}

namespace {

void disturbNormals(const Disturbance& d, int index, std::mt19937_64& rng, VariedShape& s) {
  if (d.estimated_normals)
    estimatePcaNormals(s.points, 30, s.normals);
  if (d.flips && index % 2 == 0) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (Eigen::Index i = 0; i < s.normals.cols(); ++i)
      if (unit(rng) < 0.5)
        s.normals.col(i) *= -1.0;
  }
}

std::string describe(const char* what, double size, const Disturbance& d, const char* extra) {
  std::ostringstream o;
  o << what << " size " << size << " noise " << d.noise * 100 << "% "
    << (d.estimated_normals ? "PCA" : "exact") << " normals " << extra;
  return o.str();
}

}  // namespace

VariedShape variedPrimitive(int index, std::uint64_t seed, const Disturbance& disturbance) {
  std::mt19937_64 rng(seed * 1000003u + static_cast<std::uint64_t>(index));
  std::uniform_real_distribution<double> u(-1.0, 1.0), unit(0.0, 1.0);
  const double size = std::pow(10.0, -3.0 + 6.0 * unit(rng));
  const Eigen::Vector3d axis = randomVector<3>(u, rng).normalized();
  const Eigen::Vector3d where =
      size * ((index % 3 == 1 ? 1e3 : 0.0) * Eigen::Vector3d::Ones() + randomVector<3>(u, rng));
  const auto sampling = static_cast<Sampling>((index / 5) % 3);
  const bool partial = unit(rng) < 0.5;
  PrimitiveSamplingParameters p;
  p.seed = rng();
  p.points = static_cast<std::size_t>(sampling == Sampling::uniform    ? kPoints
                                      : sampling == Sampling::gradient ? 2.5 * kPoints
                                                                       : 6 * kPoints);
  VariedShape s;
  std::ostringstream extra;
  extra << (partial ? "partial " : "")
        << (sampling == Sampling::uniform    ? "uniform"
            : sampling == Sampling::gradient ? "gradient"
                                             : "scan lines");
  double feature = size;  // the size the noise is a fraction of
  switch (index % 5) {
    case 0:
      p.primitive = Plane{axis, axis.dot(where)};
      p.extent = size;
      s.truth = SlippageType::plane;
      break;
    case 1:
      p.primitive = Sphere{where, size};
      p.cap = partial ? (50 + 70 * unit(rng)) * kDegree : kPi;
      p.axis_hint = axis.unitOrthogonal();
      s.truth = SlippageType::sphere;
      break;
    case 2: {
      const double ratio = std::pow(10.0, std::log10(0.15) + std::log10(40 / 0.15) * unit(rng));
      p.primitive = Cylinder{axis, where, size};
      p.extent = ratio * size;
      p.angle_max = partial ? (120 + 150 * unit(rng)) * kDegree : 2 * kPi;
      s.truth = SlippageType::cylinder;
      extra << " h/r " << ratio;
      break;
    }
    case 3: {
      const double alpha = (5 + 70 * unit(rng)) * kDegree;
      p.primitive = Cone{axis, where, alpha};
      p.extent_min = size * (0.2 + 0.4 * unit(rng));
      p.extent = p.extent_min + size;
      p.angle_max = partial ? (150 + 150 * unit(rng)) * kDegree : 2 * kPi;
      feature = 0.5 * (p.extent_min + p.extent) * std::tan(alpha);
      s.truth = SlippageType::cone;
      extra << " half-angle " << alpha / kDegree;
      break;
    }
    default: {
      const double ratio = std::pow(10.0, std::log10(0.06) + std::log10(0.8 / 0.06) * unit(rng));
      p.primitive = Torus{axis, where, size, ratio * size};
      p.angle_max = partial ? (90 + 180 * unit(rng)) * kDegree : 2 * kPi;
      feature = ratio * size;
      s.truth = SlippageType::torus;
      extra << " r/R " << ratio;
      break;
    }
  }
  p.noise = disturbance.noise * feature;
  samplePrimitive(p, s.points, s.normals);
  thin(sampling, rng, s.points, s.normals);
  disturbNormals(disturbance, index, rng, s);
  s.description = describe(std::string(slippageTypeName(s.truth)).c_str(), size, disturbance,
                           extra.str().c_str());
  return s;
}

VariedShape variedMotionSurface(int index, std::uint64_t seed, const Disturbance& disturbance) {
  std::mt19937_64 rng(seed * 1000003u + static_cast<std::uint64_t>(index));
  std::uniform_real_distribution<double> u(-1.0, 1.0), unit(0.0, 1.0);
  const double size = std::pow(10.0, -3.0 + 6.0 * unit(rng));
  MotionSurfaceParameters p;
  p.surface = kMotionSurfaceNames[static_cast<std::size_t>(index % 5)].first;
  p.radius = size;
  p.length = size * (1.5 + 1.5 * unit(rng));
  const double sign = unit(rng) < 0.5 ? -1.0 : 1.0;
  if (p.surface == MotionSurface::helix)
    p.pitch = sign * size * (0.15 + 0.35 * unit(rng));
  if (p.surface == MotionSurface::twisted_column)
    p.pitch = sign * p.length / ((0.25 + 0.75 * unit(rng)) * kPi);
  p.points = static_cast<std::size_t>(kPoints);
  p.noise = disturbance.noise * size;
  p.seed = rng();
  VariedShape s;
  sampleMotionSurface(p, s.points, s.normals);
  const Eigen::Matrix3d turn =
      Eigen::Quaterniond(randomVector<4>(u, rng).normalized()).toRotationMatrix();
  const Eigen::Vector3d shift =
      size * ((index % 3 == 1 ? 1e3 : 0.0) * Eigen::Vector3d::Ones() + randomVector<3>(u, rng));
  s.points = (turn * s.points).colwise() + shift;
  s.normals = turn * s.normals;
  s.axis = turn.col(2);
  s.axis_point = shift;
  switch (p.surface) {
    case MotionSurface::revolution:
      s.truth = SlippageType::revolution;
      break;
    case MotionSurface::extrusion:
    case MotionSurface::open_extrusion:
      s.truth = SlippageType::extrusion;
      break;
    default:
      s.truth = SlippageType::helix;
      s.pitch = p.pitch;
      break;
  }
  disturbNormals(disturbance, index, rng, s);
  std::ostringstream extra;
  extra << kMotionSurfaceNames[static_cast<std::size_t>(index % 5)].second << " length "
        << p.length / size << " pitch " << p.pitch / size;
  s.description = describe(std::string(slippageTypeName(s.truth)).c_str(), size, disturbance,
                           extra.str().c_str());
  return s;
}

}  // namespace slipfit::testing
