#pragma once
/// \file Seeded samplers of analytic shapes with exact normals, for tests, benchmarks and the
/// sample clouds. Each returns points on the surface with the outward unit normal.

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Core>

#include <cstdint>

namespace slipfit::testing {

using Cloud = pcl::PointCloud<pcl::PointNormal>;

/// Sphere of \a radius about \a center, area-uniform.
Cloud sampleSphere(std::size_t n, const Eigen::Vector3f& center, float radius, std::uint64_t seed);

/// Open cylinder of \a radius around the z axis through \a base, z in [0, height], area-uniform.
Cloud sampleCylinder(std::size_t n, const Eigen::Vector3f& base, float radius, float height,
                     std::uint64_t seed);

/// Closed torus about the z axis (centre-circle radius R, tube radius r), area-uniform.
Cloud sampleTorus(std::size_t n, const Eigen::Vector3f& center, float R, float r,
                  std::uint64_t seed);

/// Rectangle [x0, x1] × [y0, y1] at height z, normal +z, uniform.
Cloud samplePlane(std::size_t n, float x0, float x1, float y0, float y1, float z,
                  std::uint64_t seed);

/// Adds isotropic Gaussian noise of standard deviation \a sigma to the coordinates.
void addNoise(Cloud& cloud, float sigma, std::uint64_t seed);

/// Appends \a b to \a a.
void append(Cloud& a, const Cloud& b);

/// The benchmarks' million-point scene: a ground plane (500k points), a sphere and a torus (250k
/// each), 0.006 Gaussian noise, normals NaN (a scan's points only).
Cloud millionPointScene();

/// Largest angle in degrees between a normal and the corresponding reference, ignoring sign when
/// \a unsigned_ is true.
double maxAngleDeg(const Eigen::Matrix3Xf& normals, const Eigen::Matrix3Xf& reference,
                   bool unsigned_);

}  // namespace slipfit::testing
