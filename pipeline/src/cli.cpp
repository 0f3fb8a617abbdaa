#include "slipfit/pipeline/cli.h"

#include "slipfit/core/exceptions.h"

#include "slipfit/pipeline/cloud_io.h"
#include "slipfit/pipeline/config.h"
#include "slipfit/pipeline/errors.h"
#include "slipfit/pipeline/registry.h"
#include "slipfit/pipeline/runner.h"
#include "slipfit/pipeline/tiled_run.h"
#include "slipfit/version.h"

#include <pcl/console/print.h>
#include <pcl/exceptions.h>

#include <iomanip>
#include <new>
#include <ostream>

namespace slipfit::pipeline {

namespace {

constexpr const char* kUsage =
    "usage: slipfit run CONFIG.yaml [--set KEY=VALUE ...] [--quiet]\n"
    "       slipfit validate CONFIG.yaml [--set KEY=VALUE ...]\n"
    "       slipfit stages\n"
    "       slipfit describe STAGE|input|output|tiling|run\n"
    "KEY is input.OPTION, output.OPTION, threads, seed or TAG.OPTION (a stage's tag).\n"
    "Exit codes: 0 success, 1 run failure (input data, computation, output), 2 usage or config "
    "error.\n";

struct ConfigArgs {
  std::string config;
  std::vector<std::string> overrides;
  bool quiet = false;
};

ConfigArgs parseConfigArgs(const std::vector<std::string>& args, bool allow_quiet) {
  ConfigArgs parsed;
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--set") {
      if (i + 1 >= args.size())
        throw ConfigError("--set needs KEY=VALUE");
      parsed.overrides.push_back(args[++i]);
    } else if (a.rfind("--set=", 0) == 0) {
      parsed.overrides.push_back(a.substr(6));
    } else if (allow_quiet && (a == "--quiet" || a == "-q")) {
      parsed.quiet = true;
    } else if (!a.empty() && a[0] == '-') {
      throw ConfigError("unknown option '" + a + "' for '" + args[0] + "'");
    } else if (parsed.config.empty()) {
      parsed.config = a;
    } else {
      throw ConfigError("'" + args[0] + "' takes one config file, got also '" + a + "'");
    }
  }
  if (parsed.config.empty())
    throw ConfigError("'" + args[0] + "' needs a CONFIG.yaml");
  return parsed;
}

void describeOptions(const OptionSet& options, std::ostream& out) {
  for (const auto& o : options.all()) {
    out << "  " << o->name() << "  (" << o->type();
    if (!o->unit().empty())
      out << ", " << o->unit();
    out << ")  default: " << (o->isRequired() ? "required" : o->defaultText());
    const std::string range = o->rangeText();
    if (!range.empty())
      out << "  range: " << range;
    out << "\n      " << o->help() << "\n";
  }
}

int describe(const std::string& name, std::ostream& out) {
  OptionSet options;
  InputSection input;
  OutputSection output;
  TilingSection tiling;
  RunSettings settings;
  std::unique_ptr<Stage> stage;
  if (name == "input") {
    out << "input: the point cloud the pipeline reads\n";
    input.declare(options);
  } else if (name == "output") {
    out << "output: where the pipeline writes (all files or none)\n";
    output.declare(options);
  } else if (name == "tiling") {
    out << "tiling: an out-of-core run in tiles, off while size is 0 (docs/TILING.md)\n";
    tiling.declare(options);
  } else if (name == "run" || name == "threads" || name == "seed") {
    out << "run: the top-level settings of a config (threads, seed)\n";
    settings.declare(options);
  } else {
    const StageInfo* info = findStage(name);
    if (!info)
      throw ConfigError("unknown stage '" + name + "'; known stages: " + knownStagesText() +
                        " (and the sections input, output, tiling, run)");
    stage = info->make();
    stage->declare(options);
    out << info->name << ": " << info->summary << "\n";
    try {
      stage->prepare();
    } catch (const OptionValueError&) {
      // Some stages have no complete default (crop needs limits); their flow does not depend on
      // the options that are missing.
    } catch (const InvalidParameterError&) {
    }
    const DataFlow flow = stage->flow();
    out << "consumes: " << dataBitsText(flow.consumes)
        << "; produces: " << (flow.produces ? dataBitsText(flow.produces) : "nothing new") << "\n";
  }
  out << "options:\n";
  describeOptions(options, out);
  return kSuccess;
}

int dispatch(const std::vector<std::string>& args, std::ostream& out) {
  if (args.empty())
    throw ConfigError("no command given; try 'slipfit --help'");
  const std::string& command = args[0];
  if (command == "--help" || command == "-h" || command == "help") {
    out << kUsage;
    return kSuccess;
  }
  if (command == "--version") {
    out << "slipfit " << kVersion << "\n";
    return kSuccess;
  }
  if (command == "stages") {
    if (args.size() != 1)
      throw ConfigError("'stages' takes no arguments");
    for (const auto& info : stageRegistry())
      out << std::left << std::setw(26) << info.name << info.summary << "\n";
    return kSuccess;
  }
  if (command == "describe") {
    if (args.size() != 2)
      throw ConfigError("'describe' takes one stage name");
    return describe(args[1], out);
  }
  if (command == "validate") {
    const ConfigArgs parsed = parseConfigArgs(args, false);
    PipelineConfig config = loadConfig(parsed.config, parsed.overrides);
    checkConfigFiles(config);
    if (config.tiling.enabled())
      checkTiledRun(config);
    // The stages' contracts against what the input's header gives: a config that `run` would
    // refuse for a missing field is refused here, with run's line.
    if (!config.input.path.empty()) {
      const std::string flow = checkDataFlow(config, inputDataBits(config.input.path));
      if (!flow.empty())
        throw RunError(config.path + ": " + flow);
    }
    out << parsed.config << ": valid, " << config.stages.size()
        << (config.stages.size() == 1 ? " stage\n" : " stages\n");
    return kSuccess;
  }
  if (command == "run") {
    const ConfigArgs parsed = parseConfigArgs(args, true);
    PipelineConfig config = loadConfig(parsed.config, parsed.overrides);
    RunOptions options;
    options.quiet = parsed.quiet;
    if (config.tiling.enabled())
      runTiled(config, parsed.overrides, options, out);
    else
      runPipeline(config, options, out);
    return kSuccess;
  }
  throw ConfigError("unknown command '" + command + "'; commands: run, validate, stages, describe");
}

}  // namespace

namespace {

/// The error line: control characters in the message (a newline inside a value, a tab, an escape
/// sequence) are written as \n, \r, \t or \xHH, so that an error is always exactly one line and
/// no value can start a line of its own that passes for another "slipfit: error:".
std::string oneLine(const std::string& message) {
  std::string line;
  for (const char c : message) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '\n')
      line += "\\n";
    else if (c == '\r')
      line += "\\r";
    else if (c == '\t')
      line += "\\t";
    else if (u < 0x20 || u == 0x7f) {
      static const char* const kHex = "0123456789abcdef";
      line += "\\x";
      line += kHex[u >> 4];
      line += kHex[u & 15];
    } else {
      line += c;
    }
  }
  return line;
}

}  // namespace

int runCommandLine(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  // PCL's readers print their own diagnostics; slipfit reports one line of its own instead.
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  try {
    return dispatch(args, out);
  } catch (const ConfigError& e) {
    err << "slipfit: error: " << oneLine(e.what()) << "\n";
    return kUsageError;
  } catch (const OptionValueError& e) {
    err << "slipfit: error: " << oneLine(e.what()) << "\n";
    return kUsageError;
  } catch (const RunError& e) {
    err << "slipfit: error: " << oneLine(e.what()) << "\n";
    return kRunFailure;
  } catch (const pcl::PCLException& e) {
    err << "slipfit: error: " << oneLine(e.what()) << "\n";
    return kRunFailure;
  } catch (const std::bad_alloc&) {  // outside any stage: reading the input, writing outputs
    err << "slipfit: error: out of memory\n";
    return kRunFailure;
  } catch (const std::exception& e) {
    err << "slipfit: error: " << oneLine(e.what()) << "\n";
    return kRunFailure;
  }
}

}  // namespace slipfit::pipeline
