#pragma once
// A numeric field of a cloud read back by the pipeline (labels, codes), as 32-bit integers.
#include "slipfit/pipeline/point_data.h"

#include <cstdint>
#include <string>
#include <vector>

namespace slipfit::testing {

inline std::vector<std::int32_t> intField(const pipeline::PointData& data,
                                          const std::string& name) {
  const std::vector<double> v = data.numericField(name);
  std::vector<std::int32_t> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i)
    out[i] = static_cast<std::int32_t>(v[i]);
  return out;
}

}  // namespace slipfit::testing
