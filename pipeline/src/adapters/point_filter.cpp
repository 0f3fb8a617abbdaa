#include "point_filter.h"

#include "slipfit/pipeline/errors.h"

#include <ostream>
#include <vector>

namespace slipfit::pipeline::adapters {

void requireInputCloud(const PointData& data) {
  if (data.full)
    throw RunError("filters select input points: place this stage before the subsample stage");
}

void keepFiltered(PointData& data, const pcl::Indices& kept, RunContext& context,
                  const std::string& name, const std::string& why) {
  const std::size_t n = data.size();
  if (kept.empty())
    throw RunError("no point of the " + std::to_string(n) + " is kept (" + why + ")");
  std::vector<char> keep(n, 0);
  for (const auto i : kept)
    keep[static_cast<std::size_t>(i)] = 1;
  const std::size_t count = kept.size();  // PCL's filters select each index once
  if (count < n)
    data.keepOnly(keep);
  context.report << name << ": " << count << " of " << n << " points kept, " << n - count
                 << " dropped (" << why << ")\n";
}

}  // namespace slipfit::pipeline::adapters
