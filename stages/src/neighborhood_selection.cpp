#include "slipfit/neighborhood_selection.h"

#include "slipfit/impl/neighborhood_selection.hpp"

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
  const bool needs_radius = mode == NeighborhoodMode::radius || mode == NeighborhoodMode::hybrid;
  if (needs_radius && !radius)
    reject("radius", "unset", "'required in radius and hybrid modes'");
  if (radius && !(*radius > 0.0 && std::isfinite(*radius)))
    reject("radius", std::to_string(*radius), "'0 < radius < inf'");
  if (k < 3 || k > 10000)
    reject("k", std::to_string(k), "'3 <= k <= 10000'");
  if (max_neighbors && *max_neighbors < 3)
    reject("max_neighbors", std::to_string(*max_neighbors), "'max_neighbors >= 3'");
  if (k_min < 3)
    reject("k_min", std::to_string(k_min), "'k_min >= 3'");
  if (k_max < k_min || k_max > 10000)
    reject("k_max", std::to_string(k_max), "'k_min <= k_max <= 10000'");
  if (k_step < 1)
    reject("k_step", std::to_string(k_step), "'k_step >= 1'");
  if (threads < 0)
    reject("threads", std::to_string(threads), "'threads >= 0'");
}

template class NeighborhoodSelection<pcl::PointXYZ>;
template class NeighborhoodSelection<pcl::PointXYZI>;
template class NeighborhoodSelection<pcl::PointXYZRGB>;
template class NeighborhoodSelection<pcl::PointXYZRGBA>;
template class NeighborhoodSelection<pcl::PointNormal>;
template class NeighborhoodSelection<pcl::PointXYZRGBNormal>;
template class NeighborhoodSelection<pcl::PointXYZINormal>;

}  // namespace slipfit
