#pragma once
/// \file Registry entries of the pipeline stages (one adapter file per stage).

#include "slipfit/pipeline/stage.h"

namespace slipfit::pipeline::adapters {

StageInfo neighborhoodSelectionInfo();
StageInfo normalEstimationInfo();
StageInfo torusSamplingInfo();
StageInfo primitiveSamplingInfo();
StageInfo motionSurfaceSamplingInfo();
StageInfo primitiveFittingInfo();
StageInfo slippageClassificationInfo();
StageInfo sceneSamplingInfo();
StageInfo scanSamplingInfo();
StageInfo segmentationInfo();
StageInfo subsampleInfo();
StageInfo cropInfo();
StageInfo voxelGridInfo();
StageInfo outlierRemovalInfo();

}  // namespace slipfit::pipeline::adapters
