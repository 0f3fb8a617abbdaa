#pragma once
/// \file A run in tiles (the config's `tiling:` section; docs/TILING.md): the input streamed into
/// tiles in the work directory, the unchanged pipeline run on each tile (one after another, or
/// shared among the ranks of `mpirun`), and the tiles' segments joined into segments.ply and
/// primitives.yaml of the whole cloud. Tiles and finished tile runs are kept: a rerun of the same
/// input, tiling and config resumes after the last finished tile.

#include "slipfit/pipeline/config.h"
#include "slipfit/pipeline/runner.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace slipfit::pipeline {

/// What `validate` checks of a tiled run: the pipeline can be tiled and the work directory can be
/// used (tiling/work_directory.h). Throws ConfigError or RunError as runTiled would.
void checkTiledRun(const PipelineConfig& config);

/// Runs \a config (tiling enabled) from \a config_path with \a overrides; returns the files
/// written (on rank 0, which names and commits them; the other ranks, which write their share of
/// the tiles and of segments.ply's rows, return none). Throws ConfigError for a pipeline that
/// cannot run in tiles and RunError for a failure (nothing is written then).
std::vector<std::string> runTiled(const PipelineConfig& config,
                                  const std::vector<std::string>& overrides,
                                  const RunOptions& options, std::ostream& report);

}  // namespace slipfit::pipeline
