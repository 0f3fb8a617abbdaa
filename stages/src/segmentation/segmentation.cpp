#include "slipfit/segmentation/segmentation.h"
#include "slipfit/core/threads.h"

#include "slipfit/core/exceptions.h"
#include "slipfit/segmentation/segmentation_kernel.h"

#include <cmath>

namespace slipfit {

void SegmentationParameters::validate() const {
  validateDeclared(*this, "segmentation");
  validateThreads(threads, "segmentation");
}

SegmentationResult segmentBySlippage(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                     const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                                     const Neighborhoods& hoods,
                                     const std::vector<SlippageType>& local_types,
                                     const SegmentationParameters& parameters,
                                     const std::function<void(std::string_view)>& on_phase) {
  SegmentationKernel kernel(points, normals, hoods, local_types, parameters);
  kernel.setPhaseListener(on_phase);
  using Phase = SegmentationKernel::Phase;
  kernel.runPhases(Phase::estimate_scale, Phase::drop_non_surfaces);
  return kernel.finalize();
}

}  // namespace slipfit
