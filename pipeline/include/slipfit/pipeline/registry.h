#pragma once
/// \file The explicit stage registry (one list in registry.cpp: static self-registration would be
/// dropped by the linker from a static library).

#include "slipfit/pipeline/stage.h"

#include <string>
#include <string_view>
#include <vector>

namespace slipfit::pipeline {

const std::vector<StageInfo>& stageRegistry();
/// nullptr when unknown.
const StageInfo* findStage(std::string_view name);
/// "a, b, c".
std::string knownStagesText();

}  // namespace slipfit::pipeline
