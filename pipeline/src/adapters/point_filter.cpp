#include "point_filter.h"

#include "slipfit/pipeline/errors.h"

#include <algorithm>
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
  const std::size_t count = kept.size();  // PCL's filters select each index once
  if (count < n) {
    if (std::is_sorted(kept.begin(), kept.end())) {
      data.keepOnly(kept);
    } else {  // a grid filter's order: the points keep theirs
      pcl::Indices ascending = kept;
      std::sort(ascending.begin(), ascending.end());
      data.keepOnly(ascending);
    }
  }
  context.report << name << ": " << count << " of " << n << " points kept, " << n - count
                 << " dropped (" << why << ")\n";
}

}  // namespace slipfit::pipeline::adapters
