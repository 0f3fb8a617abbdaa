#pragma once
/// \file Running a validated pipeline: read, run every stage, write all outputs or none.

#include "slipfit/pipeline/config.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace slipfit::pipeline {

struct RunOptions {
  bool quiet = false;  ///< no report lines and no progress
  /// The outputs are the process's answer: once they are committed, an interrupt says so. False
  /// for the tiles of a tiled run, whose outputs are only its pieces.
  bool final_outputs = true;
};

/// Runs \a config; returns the files written. Throws RunError (nothing is written then).
std::vector<std::string> runPipeline(PipelineConfig& config, const RunOptions& options,
                                     std::ostream& report);

}  // namespace slipfit::pipeline
