#include "slipfit/neighborhoods/neighborhood_selection.h"
#include "slipfit/core/threads.h"

#include "slipfit/neighborhoods/impl/neighborhood_selection.hpp"

#include <pcl/point_types.h>

#include <cmath>
#include <sstream>
#include <string>

namespace slipfit {

namespace {
[[noreturn]] void reject(const char* field, const std::string& value, const char* constraint) {
  std::ostringstream os;
  os << "neighborhood parameters: " << field << " = " << value << " violates " << constraint;
  throw InvalidParameterError(os.str());
}
}  // namespace

void NeighborhoodParameters::validate() const {
  validateDeclared(*this, "neighborhood parameters");
  const bool needs_radius = mode == NeighborhoodMode::radius || mode == NeighborhoodMode::hybrid;
  if (needs_radius && !radius)
    reject("radius", "unset", "'required in radius and hybrid modes'");
  if (k_max < k_min)
    reject("k_max", std::to_string(k_max), "'k_min <= k_max'");
  validateThreads(threads, "neighborhood parameters");
}

template class NeighborhoodSelection<pcl::PointXYZ>;
template class NeighborhoodSelection<pcl::PointXYZI>;
template class NeighborhoodSelection<pcl::PointXYZRGB>;
template class NeighborhoodSelection<pcl::PointXYZRGBA>;
template class NeighborhoodSelection<pcl::PointNormal>;
template class NeighborhoodSelection<pcl::PointXYZRGBNormal>;
template class NeighborhoodSelection<pcl::PointXYZINormal>;

}  // namespace slipfit
