#include "slipfit/segmentation.h"

#include "slipfit/exceptions.h"
#include "slipfit/segmentation_kernel.h"

#include <cmath>

namespace slipfit {

void SegmentationParameters::validate() const {
  if (distance && !(*distance > 0.0 && std::isfinite(*distance)))
    throw InvalidParameterError("segmentation: distance must be > 0");
  if (!(max_angle > 0.0 && max_angle <= 1.5707963267948966 + 1e-12))
    throw InvalidParameterError("segmentation: max_angle must be in (0, 90] degrees");
  if (min_points && *min_points < 3)
    throw InvalidParameterError("segmentation: min_points must be at least 3");
  if (!(merge_factor >= 1.0 && merge_factor <= 10.0))
    throw InvalidParameterError("segmentation: merge_factor must be in [1, 10]");
  if (threads < 0)
    throw InvalidParameterError("segmentation: threads must be 0 (all cores) or positive");
}

SegmentationResult segmentBySlippage(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                     const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                                     const Neighborhoods& hoods,
                                     const std::vector<SlippageType>& local_types,
                                     const SegmentationParameters& parameters) {
  SegmentationKernel kernel(points, normals, hoods, local_types, parameters);
  kernel.estimateScale();
  kernel.growSlippageSeeds();
  kernel.growFreeSeeds();
  kernel.mergeRegions();
  kernel.reviseTypes();
  kernel.refineBoundaries();
  kernel.joinCreases();
  kernel.recoverSmallFaces();
  kernel.absorbFragments();
  kernel.mergeSettledRegions();
  kernel.dropNonSurfaces();
  return kernel.finalize();
}

}  // namespace slipfit
