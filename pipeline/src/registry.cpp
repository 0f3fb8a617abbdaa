#include "slipfit/pipeline/registry.h"

#include "adapters/adapters.h"

namespace slipfit::pipeline {

const std::vector<StageInfo>& stageRegistry() {
  // The one list of stages, in the order a pipeline usually runs them.
  static const std::vector<StageInfo> registry = {
      adapters::torusSamplingInfo(),
      adapters::primitiveSamplingInfo(),
      adapters::motionSurfaceSamplingInfo(),
      adapters::cropInfo(),
      adapters::outlierRemovalInfo(),
      adapters::voxelGridInfo(),
      adapters::subsampleInfo(),
      adapters::neighborhoodSelectionInfo(),
      adapters::normalEstimationInfo(),
      adapters::slippageClassificationInfo(),
      adapters::primitiveFittingInfo(),
      adapters::sceneSamplingInfo(),
      adapters::scanSamplingInfo(),
      adapters::segmentationInfo(),
  };
  return registry;
}

const StageInfo* findStage(std::string_view name) {
  for (const auto& info : stageRegistry())
    if (info.name == name)
      return &info;
  return nullptr;
}

std::string knownStagesText() {
  std::string s;
  for (const auto& info : stageRegistry())
    s += (s.empty() ? "" : ", ") + std::string(info.name);
  return s;
}

}  // namespace slipfit::pipeline
