#include "slipfit/neighborhoods/normal_estimation.h"
#include "slipfit/core/threads.h"

#include "slipfit/neighborhoods/impl/normal_estimation.hpp"

#include <pcl/point_types.h>

#include <cmath>
#include <sstream>

namespace slipfit {

void NormalParameters::validate() const {
  auto reject = [](const char* field, const std::string& value, const char* constraint) {
    std::ostringstream os;
    os << "normal parameters: " << field << " = " << value << " violates " << constraint;
    throw InvalidParameterError(os.str());
  };
  validateDeclared(*this, "normal parameters");
  if (viewpoint && !viewpoint->allFinite())
    reject("viewpoint", "non-finite", "'finite coordinates'");
  validateThreads(threads, "normal parameters");
}

template class OrientedNormalEstimation<pcl::PointXYZ, pcl::Normal>;
template class OrientedNormalEstimation<pcl::PointXYZ, pcl::PointNormal>;
template class OrientedNormalEstimation<pcl::PointXYZRGB, pcl::Normal>;
template class OrientedNormalEstimation<pcl::PointNormal, pcl::Normal>;
template class OrientedNormalEstimation<pcl::PointNormal, pcl::PointNormal>;
template class OrientedNormalEstimation<pcl::PointXYZRGBNormal, pcl::Normal>;

}  // namespace slipfit
