#pragma once
/// \file Loading a YAML pipeline: parse, apply --set overrides, validate every stage before any
/// runs. Every error is a ConfigError that names file:line:column, the stage tag and the key.

#include "slipfit/pipeline/cloud_io.h"
#include "slipfit/pipeline/options.h"
#include "slipfit/pipeline/stage.h"

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace slipfit::pipeline {

/// The `input:` section.
struct InputSection {
  std::string path;
  NanPolicy nan = NanPolicy::skip;  // PCL's tools drop NaN points (removeNaNFromPointCloud)
  /// Not an option: the sensor a file that carries none was seen by (origin in the file's
  /// coordinates, orientation w, x, y, z). A tiled run sets it for its tiles from the input's.
  std::optional<std::array<double, 7>> sensor;
  void declare(OptionSet& options);
};

enum class PlyEncoding { binary, ascii };
constexpr std::array<std::pair<PlyEncoding, std::string_view>, 2> kPlyEncodingNames{{
    {PlyEncoding::binary, "binary"},
    {PlyEncoding::ascii, "ascii"},
}};

/// The `output:` section.
struct OutputSection {
  std::string dir = "out";
  PlyEncoding format = PlyEncoding::binary;
  std::string cloud = "cloud.ply";
  void declare(OptionSet& options);
};

/// The `tiling:` section: an out-of-core run in tiles (docs/TILING.md). Off while size is 0.
struct TilingSection {
  /// Largest edge of a tile's core in the cloud's units (x-y); 0: untiled; unset ("auto"): chosen
  /// from the input's extent and max_points (autoTileSize, tiling/tiler.h).
  std::optional<double> size = 0.0;
  double buffer = 0.0;  ///< width of the band each tile also reads; 0: a tenth of size
  /// The most points a tile's core may hold: denser tiles are split into quarters; 0: no limit.
  std::uint64_t max_points = kDefaultMaxPoints;
  static constexpr std::uint64_t kDefaultMaxPoints = 1000000;
  std::string workdir;  ///< tiles and per-tile results; "": <output.dir>/tiles
  void declare(OptionSet& options);
  bool enabled() const { return !size || *size > 0.0; }
  /// The buffer of tiles of edge \a edge (the size, once chosen).
  double bufferWidth(double edge) const { return buffer > 0.0 ? buffer : 0.1 * edge; }
};

/// Top-level settings besides the sections.
struct RunSettings {
  int threads = 0;
  std::uint64_t seed = 1;
  void declare(OptionSet& options);
};

struct ConfiguredStage {
  std::string type;
  std::string tag;
  std::string where;  ///< "file:line:col" of the stage entry
  std::unique_ptr<Stage> stage;
};

struct PipelineConfig {
  std::string path;
  InputSection input;
  OutputSection output;
  TilingSection tiling;
  RunSettings settings;
  std::vector<ConfiguredStage> stages;
};

/// Loads and validates \a path with "KEY=VALUE" \a overrides (KEY: input.X, output.X, threads,
/// seed or TAG.OPTION). Throws ConfigError.
PipelineConfig loadConfig(const std::string& path, const std::vector<std::string>& overrides);

/// The checks on the file system that `validate` and `run` make before anything runs (RunError,
/// exit 1; ConfigError for two outputs of one name): the input is a readable regular file,
/// output.dir exists as a directory or can be created, no two outputs share a name, and no
/// output is the input. Paths are taken as given: relative ones from the working directory.
void checkConfigFiles(const PipelineConfig& config);

/// Checks that each stage's inputs are available when it runs, given the data bits the input
/// provides. Returns "" or the problem.
std::string checkDataFlow(const PipelineConfig& config, unsigned input_bits);

/// The first stage that reads the input's own normals (it consumes normals before any stage
/// produces them), or nullptr.
const ConfiguredStage* firstUserOfInputNormals(const PipelineConfig& config);

}  // namespace slipfit::pipeline
