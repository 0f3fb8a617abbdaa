#include "slipfit/pipeline/tiled_run.h"
#include "slipfit/core/threads.h"

#include "slipfit/filters/subsampling.h"
#include "slipfit/pipeline/cloud_stream.h"
#include "slipfit/pipeline/errors.h"
#include "slipfit/pipeline/output_files.h"
#include "slipfit/pipeline/progress.h"

#include "tiling/tile_job.h"
#include "tiling/tile_merge.h"
#include "tiling/tiler.h"
#include "tiling/work_distribution.h"

#include <yaml-cpp/yaml.h>

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <mutex>
#include <optional>
#include <ostream>
#include <sstream>

namespace slipfit::pipeline {

namespace fs = std::filesystem;
using namespace tiling;

namespace {

class NullBuffer : public std::streambuf {
 protected:
  int overflow(int c) override { return c; }
};

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Writes \a text to \a path through a temporary file and a rename.
void writeAtomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << text;
    out.close();
    if (!out)
      throw RunError("'" + tmp + "': write failed (disk full?)");
  }
  fs::rename(tmp, path);
}

/// The segmentation stage the tiles end with; ConfigError when the pipeline cannot be tiled.
const ConfiguredStage& tiledSegmentation(const PipelineConfig& config) {
  const std::string why = config.path + ": section 'tiling': ";
  if (config.input.path.empty())
    throw ConfigError(why + "a tiled run reads an input cloud; this config has none");
  if (config.stages.empty() || config.stages.back().type != "segmentation")
    throw ConfigError(why + "a tiled run ends with a segmentation stage (its segments are " +
                      "joined across tiles); the last stage here is '" +
                      (config.stages.empty() ? "none" : config.stages.back().type) + "'");
  if (!config.output.cloud.empty())
    throw ConfigError(why + "output.cloud is not written by a tiled run; set it to ''");
  return config.stages.back();
}

/// A subsample stage's `points` is a budget for the whole cloud. In voxel mode the tiles all use
/// the leaf the untiled run would choose (voxelLeafForTarget, each tile counting the voxels whose
/// corner lies in its core: the counts add up to the whole cloud's), so that every tile is
/// analysed at the untiled run's voxels; in random mode each tile gets its share of the budget.
/// A given `leaf` is kept as it is. Returns, per subsample stage, the override for every tile
/// ("TAG.leaf=L") or a budget to scale by the tile's share (TAG, points).
struct AnalysisBudgets {
  std::vector<std::string> every_tile;
  std::vector<std::pair<std::string, double>> shares;
  std::vector<std::string> forTile(std::uint64_t tile_points, std::uint64_t cloud_points) const {
    std::vector<std::string> o = every_tile;
    for (const auto& [tag, whole] : shares) {
      const double share = whole * static_cast<double>(tile_points) /
                           static_cast<double>(std::max<std::uint64_t>(cloud_points, 1));
      o.push_back(tag + ".points=" +
                  std::to_string(static_cast<std::uint64_t>(std::max(100.0, std::ceil(share)))));
    }
    return o;
  }
};

/// With \a count false only the shares (the every-tile overrides come from the leader).
AnalysisBudgets analysisBudgets(const PipelineConfig& config, const TilingManifest& manifest,
                                const TileGrid& grid, const std::string& tiles_dir, bool count) {
  AnalysisBudgets budgets;
  for (const ConfiguredStage& s : config.stages) {
    if (s.type != "subsample")
      continue;
    OptionSet options;  // declared anew: each option's "default" is its configured value
    s.stage->declare(options);
    const Option* points = options.find("points");
    const Option* mode = options.find("mode");
    const Option* leaf = options.find("leaf");
    const Option* origin_option = options.find("origin");
    if (!points || !mode || !leaf || !origin_option)
      continue;
    const double whole = std::stod(points->defaultText());
    if (mode->defaultText() != "voxel") {
      if (leaf->defaultText() == "unset")
        budgets.shares.emplace_back(s.tag, whole);
      continue;
    }
    if (!count)
      continue;
    // The untiled run's grid: its lowest corner as the voxels' origin, unless one is given.
    const Eigen::Vector3d origin(manifest.lo[0], manifest.lo[1], manifest.lo[2]);
    std::ostringstream o;
    o << std::setprecision(17);
    if (origin_option->defaultText() == "unset") {
      o << s.tag << ".origin=[" << origin.x() << ", " << origin.y() << ", " << origin.z() << "]";
      budgets.every_tile.push_back(o.str());
      o.str("");
    }
    if (leaf->defaultText() != "unset")
      continue;  // a given leaf is every tile's
    if (whole >= static_cast<double>(manifest.points)) {
      budgets.every_tile.push_back(s.tag + ".points=" + std::to_string(manifest.points));
      continue;  // untiled, every point is analysed: so in every tile
    }
    // The untiled run's leaf search: its box (sizes in float, as the stage sees float coordinates).
    Eigen::Vector3d sizes;
    for (int a = 0; a < 3; ++a)
      sizes[a] = static_cast<double>(static_cast<float>(manifest.hi[a]) -
                                     static_cast<float>(manifest.lo[a]));
    const double chosen = voxelLeafForTarget(sizes, static_cast<std::size_t>(whole), [&](double l) {
      std::size_t n = 0;
      for (const TileInfo& t : manifest.tiles) {
        CloudStream in(tiles_dir + "/" + t.name() + ".ply");
        Eigen::Matrix3Xd xyz;
        in.read(0, in.size(), xyz);
        n += occupiedVoxels(xyz, l, origin, [&](const Eigen::Vector3d& corner) {
          return grid.owner(corner.x(), corner.y()) == t.key;
        });
      }
      return n;
    });
    o << s.tag << ".leaf=" << chosen;
    budgets.every_tile.push_back(o.str());
  }
  return budgets;
}

/// What the tile runs compute from: every stage's options as configured (declared anew: each
/// option's "default" is its configured value), the NaN policy and the seed — not the file names
/// or the thread count, which do not change the results, nor how the values were given.
std::string effectiveConfig(const PipelineConfig& config) {
  std::ostringstream text;
  text << "input.nan: " << static_cast<int>(config.input.nan) << "\nseed: " << config.settings.seed
       << "\n";
  for (const ConfiguredStage& s : config.stages) {
    OptionSet options;
    s.stage->declare(options);
    text << s.type << " " << s.tag << ":";
    for (const auto& o : options.all())
      text << " " << o->name() << "=" << o->defaultText();
    text << "\n";
  }
  return text.str();
}

/// The segmentation stage's picture, as configured (its options declared anew: each option's
/// "default" is its configured value); nullopt when it writes none.
std::optional<RenderRequest> renderRequest(const ConfiguredStage& segmentation) {
  OptionSet configured;
  segmentation.stage->declare(configured);
  const Option* name = configured.find("render");
  if (!name || name->defaultText().empty())
    return std::nullopt;
  RenderRequest request;
  request.name = name->defaultText();
  OptionSet camera;
  camera.bind(request.camera);
  for (const auto& option : camera.all()) {
    const Option* given = configured.find(option->name());
    if (given && given->defaultText() != "unset")
      option->parse(YAML::Load(given->defaultText()));
  }
  return request;
}

/// The work directory, checked to be empty or a tiling's own (its manifest.yaml).
std::string workDirectory(const PipelineConfig& config) {
  const std::string dir =
      config.tiling.workdir.empty() ? config.output.dir + "/tiles" : config.tiling.workdir;
  if (fs::exists(dir)) {
    if (!fs::is_directory(dir))
      throw RunError("tiling.workdir '" + dir + "' is not a directory");
    if (!fs::is_empty(dir) && !fs::exists(dir + "/manifest.yaml") && !fs::exists(dir + "/tiles"))
      throw RunError("tiling.workdir '" + dir +
                     "' holds files that are not a tiled run's; give an empty or new directory");
  }
  return dir;
}

}  // namespace

std::vector<std::string> runTiled(const PipelineConfig& config,
                                  const std::vector<std::string>& overrides,
                                  const RunOptions& options, std::ostream& report_stream) {
  const ConfiguredStage& segmentation = tiledSegmentation(config);
  checkConfigFiles(config);
  WorkDistribution work;  // one process, or the ranks of mpirun
  NullBuffer null_buffer;
  std::ostream null_stream(&null_buffer);
  std::ostream& report = options.quiet || !work.leader() ? null_stream : report_stream;
  Progress progress(!options.quiet && work.leader());

  const std::string dir = workDirectory(config);
  const std::string tiles_dir = dir + "/tiles", runs_dir = dir + "/runs";
  const std::string manifest_path = dir + "/manifest.yaml";
  const TileGrid grid(config.tiling.size, config.tiling.bufferWidth());
  const auto start = std::chrono::steady_clock::now();
  const auto seconds = [](auto since) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
  };

  // 1. Tiles: reused when the manifest is of this input and tiling, else written anew.
  TilingManifest manifest;
  std::string failure;
  if (work.leader()) {
    try {
      TilingManifest old;
      std::uint64_t bytes = 0;
      std::int64_t mtime = 0;
      inputStamp(config.input.path, bytes, mtime);
      if (readManifest(manifest_path, old) && old.input == config.input.path &&
          old.input_bytes == bytes && old.input_mtime == mtime && old.size == grid.size() &&
          old.buffer == grid.buffer()) {
        manifest = old;
        report << "tiling: reusing " << manifest.tiles.size() << " tiles in " << tiles_dir << "\n";
      } else {
        fs::remove(manifest_path);
        fs::remove(dir + "/analysis");
        fs::remove_all(tiles_dir);
        fs::remove_all(runs_dir);
        progress.begin(1, 3, "tile " + config.input.path);
        manifest = writeTiles(config.input.path, config.input.nan, grid, tiles_dir,
                              [](std::uint64_t, std::uint64_t) {});
        progress.end();
        writeAtomically(manifest_path, manifestText(manifest));
        report << "tiling: " << manifest.points << " points";
        if (manifest.dropped)
          report << " (" << manifest.dropped << " with a non-finite coordinate dropped)";
        report << " into " << manifest.tiles.size() << " tiles of " << grid.size() << " (buffer "
               << grid.buffer() << ") in " << tiles_dir << ", " << std::fixed
               << std::setprecision(2) << seconds(start) << " s\n"
               << std::defaultfloat;
      }
    } catch (const std::exception& e) {
      failure = e.what();
    } catch (...) {
      failure = "tiling failed";
    }
  }
  work.shareFailure(failure);
  if (!work.leader())
    readManifest(manifest_path, manifest);

  // The analysis density of the untiled run, in every tile.
  AnalysisBudgets budgets;
  failure.clear();
  if (work.leader()) {
    try {
      std::string fingerprint = effectiveConfig(config);
      // The leaf search reads every tile a few times: its result is kept for reruns of this
      // config on these tiles (the file goes with the tiles when they are written anew).
      const std::string cache = dir + "/analysis", key = fingerprint + "\n--\n";
      std::string text = readText(cache);
      if (text.rfind(key, 0) == 0) {
        text = text.substr(key.size());
        std::istringstream lines(text);
        budgets.shares = analysisBudgets(config, manifest, grid, tiles_dir, false).shares;
        for (std::string line; std::getline(lines, line);)
          budgets.every_tile.push_back(line);
      } else {
        budgets = analysisBudgets(config, manifest, grid, tiles_dir, true);
        text.clear();
        for (const auto& o : budgets.every_tile)
          text += o + "\n";
        writeAtomically(cache, key + text);
      }
      // Runs of another config (or another analysis density) are not reused.
      fingerprint += "\n" + text;
      fs::create_directories(runs_dir);
      if (readText(runs_dir + "/config") != fingerprint) {
        fs::remove_all(runs_dir);
        fs::create_directories(runs_dir);
        writeAtomically(runs_dir + "/config", fingerprint);
      }
      writeAtomically(runs_dir + "/analysis", text);
      for (const auto& o : budgets.every_tile)
        report << "tiling: every tile analysed with " << o << " (as untiled)\n";
    } catch (const std::exception& e) {
      failure = e.what();
    }
  }
  work.shareFailure(failure);
  if (!work.leader()) {  // the leader's choice, read back (no second count)
    std::istringstream lines(readText(runs_dir + "/analysis"));
    for (std::string line; std::getline(lines, line);)
      budgets.every_tile.push_back(line);
    budgets.shares = analysisBudgets(config, manifest, grid, tiles_dir, false).shares;
  }

  // 2. The tiles' runs: the unchanged pipeline on each tile, its report in the tile's directory.
  // Tiles are independent: a process runs as many at a time as it has threads, each tile on one
  // thread (more than one when fewer tiles than threads are left). Whole tiles in parallel use
  // the cores better than one tile's stages do, and the outputs do not depend on the threads.
  const auto tiles_start = std::chrono::steady_clock::now();
  std::size_t to_run = 0;
  for (const TileInfo& tile : manifest.tiles)
    to_run += tileDone(runs_dir + "/" + tile.name()) ? 0 : 1;
  const int threads = resolveThreads(config.settings.threads);
  const int workers =
      static_cast<int>(std::max<std::size_t>(1, std::min<std::size_t>(threads, to_run)));
  std::vector<std::string> tile_overrides = overrides;
  tile_overrides.push_back("tiling.size=0");
  tile_overrides.push_back("output.cloud=''");
  tile_overrides.push_back(segmentation.tag + ".render=''");
  tile_overrides.push_back("threads=" + std::to_string(std::max(1, threads / workers)));
  const std::vector<std::string> names = segmentation.stage->outputFiles();  // report, segments
  const std::string report_name = names.at(0), segments_name = names.at(1);
  std::atomic<std::size_t> ran{0};
  std::mutex progress_mutex;
  failure.clear();
  try {
    work.forEachTile(manifest.tiles.size(), workers, [&](std::size_t t) {
      const TileInfo& tile = manifest.tiles[t];
      const std::string run_dir = runs_dir + "/" + tile.name();
      if (tileDone(run_dir))
        return;
      const auto tile_start = std::chrono::steady_clock::now();
      std::vector<std::string> o = tile_overrides;
      for (const std::string& budget : budgets.forTile(tile.points, manifest.points))
        o.push_back(budget);
      o.push_back("input.path=" + tiles_dir + "/" + tile.name() + ".ply");
      o.push_back("output.dir=" + run_dir);
      PipelineConfig tile_config = loadConfig(config.path, o);
      RunOptions quiet;
      quiet.quiet = true;
      quiet.final_outputs = false;  // a tile's outputs are not the run's
      try {
        runPipeline(tile_config, quiet, null_stream);
        summariseTile(run_dir, segments_name, report_name);
      } catch (const RunError& e) {
        throw RunError("tile " + tile.name() + ": " + e.what());
      }
      const std::size_t done = ++ran;
      const std::lock_guard<std::mutex> lock(progress_mutex);
      progress.step(
          2, 3,
          "tile " + std::to_string(done) + "/" + std::to_string(to_run) + " (" + tile.name() + ")",
          seconds(tile_start));
    });
  } catch (const std::exception& e) {
    failure = e.what();
  }
  work.shareFailure(failure);
  const std::size_t ran_total = work.sum(ran.load());
  report << "tiling: " << ran_total << " tiles run, " << manifest.tiles.size() - ran_total
         << " already done, " << std::fixed << std::setprecision(2) << seconds(tiles_start)
         << " s\n"
         << std::defaultfloat;

  // 3. The merge, on the leader.
  std::vector<std::string> written;
  failure.clear();
  if (work.leader()) {
    try {
      const auto merge_start = std::chrono::steady_clock::now();
      progress.begin(3, 3, "merge " + std::to_string(manifest.tiles.size()) + " tiles");
      OutputFiles outputs(config.output.dir);
      outputs.protect(config.input.path);
      const std::optional<RenderRequest> render = renderRequest(segmentation);
      const MergeSummary s = mergeTiles(manifest, runs_dir, segments_name, report_name,
                                        render ? &*render : nullptr, threads, outputs);
      written = outputs.commit();
      progress.end();
      report << "segmentation: " << s.segments << " segments from " << s.pieces
             << " tile segments (" << s.joins << " joins across tiles), " << s.assigned << "/"
             << s.points << " points assigned\n";
      report << "  merge: " << std::fixed << std::setprecision(2) << seconds(merge_start)
             << " s, whole run " << seconds(start) << " s\n"
             << std::defaultfloat;
      for (const auto& path : written)
        report << "wrote " << path << "\n";
    } catch (const std::exception& e) {
      failure = e.what();
    }
  }
  work.shareFailure(failure);
  return written;
}

}  // namespace slipfit::pipeline
