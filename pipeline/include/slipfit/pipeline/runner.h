#pragma once
/// \file Running a validated pipeline: read, run every stage, write all outputs or none.

#include "slipfit/pipeline/config.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace slipfit::pipeline {

struct RunOptions {
  bool quiet = false;  ///< no report lines and no progress
};

/// Runs \a config; returns the files written. Throws RunError (nothing is written then).
std::vector<std::string> runPipeline(PipelineConfig& config, const RunOptions& options,
                                     std::ostream& report);

}  // namespace slipfit::pipeline
