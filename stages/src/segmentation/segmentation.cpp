#include "slipfit/segmentation/segmentation.h"
#include "slipfit/core/threads.h"

#include "slipfit/core/exceptions.h"
#include "slipfit/segmentation/kinematic_merge.h"
#include "slipfit/segmentation/segmentation_kernel.h"

#include <chrono>
#include <cmath>

namespace slipfit {

void SegmentationParameters::validate() const {
  validateDeclared(*this, "segmentation");
  validateThreads(threads, "segmentation");
  if (!(noise_sample_share > 0.0 && noise_sample_share <= 1.0))
    throw InvalidParameterError("segmentation: noise_sample_share " +
                                std::to_string(noise_sample_share) + " is not in (0, 1]");
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
  kernel.runPhases(Phase::estimate_scale, kLastSegmentationPhase);
  SegmentationResult result = kernel.finalize();
  if (parameters.surfaces == SegmentSurfaces::kinematic) {
    if (on_phase)
      on_phase("merge_kinematic_surfaces");
    const auto start = std::chrono::steady_clock::now();
    result.kinematic = mergeKinematicSurfaces(points, normals, hoods, result);
    result.timings.push_back(
        {"merge_kinematic_surfaces",
         std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()});
  }
  return result;
}

}  // namespace slipfit
