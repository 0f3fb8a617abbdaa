#include "point_filter.h"

#include "slipfit/pipeline/errors.h"

#include <ostream>
#include <vector>

namespace slipfit::pipeline::adapters {

void requireInputCloud(const PointData& data) {
  if (data.full)
    throw RunError("filters select input points: place this stage before the subsample stage");
}

void keepFiltered(PointData& data, const FilterSelection& selection, RunContext& context,
                  const std::string& name) {
  const std::size_t n = data.size();
  const pcl::Indices& kept = selection.kept;
  if (kept.empty())
    throw RunError("no point of the " + std::to_string(n) + " is kept (" + selection.why + ")");
  const std::size_t count = kept.size();  // PCL's filters select each index once
  if (count < n)
    data.keepOnly(kept);  // ascending, as every filter returns them
  context.report << name << ": " << count << " of " << n << " points kept, " << n - count
                 << " dropped (" << selection.why << ")\n";
}

}  // namespace slipfit::pipeline::adapters
