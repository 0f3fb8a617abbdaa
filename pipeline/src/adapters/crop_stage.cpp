#include "adapters.h"
#include "point_filter.h"

#include "slipfit/filters/point_filters.h"

#include <vector>

namespace slipfit::pipeline::adapters {

StageInfo cropInfo() {
  return {"crop",
          "keeps the points with one coordinate in [min, max] (PCL's PassThrough) and/or inside "
          "an axis-aligned box (PCL's CropBox), or outside them with negative; the others are "
          "absent from every output",
          [] {
            return std::unique_ptr<Stage>(new FilterStage<CropParameters>(
                "crop",
                [](const PointData& data, const CropParameters& p, std::vector<Eigen::Vector3f>&) {
                  // The limits are in the input's frame; the points are at its coordinates −
                  // frame.shift.
                  return crop(data.cloud, p, data.frame.shift);
                }));
          }};
}

}  // namespace slipfit::pipeline::adapters
