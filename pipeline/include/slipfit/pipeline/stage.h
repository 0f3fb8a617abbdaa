#pragma once
/// \file The pipeline's view of a stage: declared options, a data-flow contract, and one run().

#include "slipfit/pipeline/options.h"
#include "slipfit/pipeline/point_data.h"

#include <cstdint>
#include <iosfwd>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace slipfit::pipeline {

class OutputFiles;
class OutputFiles;
class Progress;

/// What a configured stage consumes and produces (DataBits).
struct DataFlow {
  unsigned consumes = kPoints;
  unsigned produces = 0;
};

/// Shared settings of one run.
struct RunContext {
  Progress& progress;
  std::ostream& report;  ///< one-line summaries (silent with --quiet)
  int threads = 0;       ///< 0: all cores
  std::uint64_t seed = 0;
  /// Extra output files (meshes, reports): written under temporary names, renamed only when the
  /// whole run succeeds.
  OutputFiles* outputs = nullptr;
  /// Whether anything after this stage reads the stage fields (a later stage, output.cloud). A
  /// stage that carries a subsampled analysis back to every point may drop them otherwise: at
  /// 10 million points they are hundreds of MB nobody writes.
  bool fields_used_later = true;
};

/// A pipeline stage adapts one algorithm of slipfit::stages to PointData.
class Stage {
 public:
  virtual ~Stage() = default;
  /// Binds every option to a member; called once, on a fresh object, before parsing.
  virtual void declare(OptionSet& options) = 0;
  /// Cross-option checks after parsing (throws OptionValueError or InvalidParameterError).
  virtual void prepare() {}
  /// Valid after prepare().
  virtual DataFlow flow() const = 0;
  /// Valid after prepare(): the names of the files run() adds to output.dir (those known before
  /// it runs), so that `validate` can refuse two outputs of one name or an output over the input.
  virtual std::vector<std::string> outputFiles() const { return {}; }
  /// Runs on \a data; throws on failure (the pipeline reports it and writes nothing).
  virtual void run(PointData& data, RunContext& context) = 0;
};

/// A registry entry.
struct StageInfo {
  std::string_view name;
  std::string_view summary;
  std::unique_ptr<Stage> (*make)();
};

}  // namespace slipfit::pipeline
