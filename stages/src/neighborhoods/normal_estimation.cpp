#include "slipfit/neighborhoods/normal_estimation.h"

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
  if (threads < 0)
    reject("threads", std::to_string(threads), "'threads >= 0'");
}

template class NormalEstimation<pcl::PointXYZ, pcl::Normal>;
template class NormalEstimation<pcl::PointXYZ, pcl::PointNormal>;
template class NormalEstimation<pcl::PointXYZRGB, pcl::Normal>;
template class NormalEstimation<pcl::PointNormal, pcl::Normal>;
template class NormalEstimation<pcl::PointNormal, pcl::PointNormal>;
template class NormalEstimation<pcl::PointXYZRGBNormal, pcl::Normal>;

}  // namespace slipfit
