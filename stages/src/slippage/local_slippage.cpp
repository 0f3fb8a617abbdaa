#include "slipfit/slippage/local_slippage.h"

#include "slipfit/slippage/impl/local_slippage.hpp"

#include <pcl/point_types.h>

namespace slipfit {

Eigen::Vector3d slippageDirection(const SlippageResult& r, const Eigen::Vector3d& point) {
  if (r.normal)
    return *r.normal;
  if (r.center)
    return (*r.center - point).normalized();
  if (r.axis)
    return *r.axis;
  return Eigen::Vector3d::Zero();
}

template class LocalSlippage<pcl::PointNormal>;
template class LocalSlippage<pcl::PointXYZRGBNormal>;
template class LocalSlippage<pcl::PointXYZINormal>;

}  // namespace slipfit
