#include "adapters.h"
#include "point_filter.h"

#include "slipfit/filters/point_filters.h"

#include <vector>

namespace slipfit::pipeline::adapters {

StageInfo outlierRemovalInfo() {
  return {"outlier_removal",
          "drops isolated points (PCL's StatisticalOutlierRemoval or RadiusOutlierRemoval): they "
          "are absent from every output",
          [] {
            return std::unique_ptr<Stage>(new FilterStage<OutlierRemovalParameters>(
                "outlier_removal",
                [](const PointData& data, const OutlierRemovalParameters& p,
                   std::vector<Eigen::Vector3f>&) { return removeOutliers(data.cloud, p); }));
          }};
}

}  // namespace slipfit::pipeline::adapters
