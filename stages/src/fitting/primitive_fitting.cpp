#include "slipfit/fitting/primitive_fitting.h"

#include "slipfit/fitting/impl/primitive_fitting.hpp"

#include <pcl/point_types.h>

namespace slipfit {

pcl::ModelCoefficients toModelCoefficients(const Primitive& primitive) {
  pcl::ModelCoefficients c;
  auto push = [&](const Eigen::Vector3d& v) {
    for (int k = 0; k < 3; ++k)
      c.values.push_back(static_cast<float>(v[k]));
  };
  std::visit(
      [&](const auto& s) {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, Plane>) {
          push(s.normal);
          c.values.push_back(static_cast<float>(-s.d));
        } else if constexpr (std::is_same_v<T, Sphere>) {
          push(s.center);
          c.values.push_back(static_cast<float>(s.radius));
        } else if constexpr (std::is_same_v<T, Cylinder>) {
          push(s.point);
          push(s.axis);
          c.values.push_back(static_cast<float>(s.radius));
        } else if constexpr (std::is_same_v<T, Torus>) {
          c.values.push_back(static_cast<float>(s.major_radius));
          c.values.push_back(static_cast<float>(s.minor_radius));
          push(s.center);
          push(s.axis);
        } else {
          push(s.apex);
          push(s.axis);
          c.values.push_back(static_cast<float>(s.half_angle));
        }
      },
      primitive);
  return c;
}

template class PrimitiveFitting<pcl::PointXYZ, pcl::Normal>;
template class PrimitiveFitting<pcl::PointXYZ, pcl::PointNormal>;
template class PrimitiveFitting<pcl::PointNormal, pcl::PointNormal>;
template class PrimitiveFitting<pcl::PointXYZRGBNormal, pcl::PointXYZRGBNormal>;

}  // namespace slipfit
