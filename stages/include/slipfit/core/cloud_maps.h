#pragma once
/// \file Eigen views (no copies) of the coordinates and normals stored in PCL point clouds, so that
/// the maths kernels work on plain 3×N matrices whatever the point type.

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/type_traits.h>

#include <Eigen/Core>

namespace slipfit {

/// A 3×N view with a column stride: column i is point i's coordinates (or normal).
using Coords3Map = Eigen::Map<Eigen::Matrix3Xf, Eigen::Unaligned, Eigen::OuterStride<>>;
using ConstCoords3Map = Eigen::Map<const Eigen::Matrix3Xf, Eigen::Unaligned, Eigen::OuterStride<>>;

namespace detail {
template <typename PointT>
constexpr int floatStride() {
  static_assert(sizeof(PointT) % sizeof(float) == 0, "point type is not a whole number of floats");
  return static_cast<int>(sizeof(PointT) / sizeof(float));
}
}  // namespace detail

/// x, y, z of every point of \a cloud as a 3×N matrix view. The cloud must outlive the view.
template <typename PointT>
ConstCoords3Map coordinates(const pcl::PointCloud<PointT>& cloud) {
  const float* base = cloud.empty() ? nullptr : reinterpret_cast<const float*>(cloud.data());
  return {base, 3, static_cast<Eigen::Index>(cloud.size()),
          Eigen::OuterStride<>(detail::floatStride<PointT>())};
}

/// normal_x, normal_y, normal_z of every point of \a cloud as a writable 3×N matrix view.
template <typename PointT>
Coords3Map normals(pcl::PointCloud<PointT>& cloud) {
  constexpr auto offset = pcl::traits::offset<PointT, pcl::fields::normal_x>::value;
  float* base = cloud.empty()
                    ? nullptr
                    : reinterpret_cast<float*>(reinterpret_cast<char*>(cloud.data()) + offset);
  return {base, 3, static_cast<Eigen::Index>(cloud.size()),
          Eigen::OuterStride<>(detail::floatStride<PointT>())};
}

/// Read-only normals view.
template <typename PointT>
ConstCoords3Map normals(const pcl::PointCloud<PointT>& cloud) {
  constexpr auto offset = pcl::traits::offset<PointT, pcl::fields::normal_x>::value;
  const float* base =
      cloud.empty()
          ? nullptr
          : reinterpret_cast<const float*>(reinterpret_cast<const char*>(cloud.data()) + offset);
  return {base, 3, static_cast<Eigen::Index>(cloud.size()),
          Eigen::OuterStride<>(detail::floatStride<PointT>())};
}

}  // namespace slipfit
