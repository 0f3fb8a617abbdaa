#include "slipfit/pipeline/tiled_run.h"
#include "slipfit/core/threads.h"

#include "slipfit/filters/subsampling.h"
#include "slipfit/pipeline/cloud_stream.h"
#include "slipfit/pipeline/errors.h"
#include "slipfit/pipeline/output_files.h"
#include "slipfit/pipeline/progress.h"
#include "slipfit/pipeline/tile_roles.h"

#include "tiling/packed_values.h"
#include "tiling/tile_job.h"
#include "tiling/tile_merge.h"
#include "tiling/tiler.h"
#include "tiling/work_directory.h"
#include "tiling/work_distribution.h"

#include "digest.h"
#include "null_buffer.h"

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
#include <new>
#include <optional>
#include <ostream>
#include <sstream>

namespace slipfit::pipeline {

namespace fs = std::filesystem;
using namespace tiling;

namespace {

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

/// The stage the tiles end with, whose segments are joined across tiles; ConfigError when the
/// pipeline cannot be tiled.
JoinedAcrossTiles& joinedStage(const PipelineConfig& config) {
  const std::string why = config.path + ": section 'tiling': ";
  if (config.input.path.empty())
    throw ConfigError(why + "a tiled run reads an input cloud; this config has none");
  auto* joined = config.stages.empty()
                     ? nullptr
                     : dynamic_cast<JoinedAcrossTiles*>(config.stages.back().stage.get());
  if (!joined)
    throw ConfigError(why + "a tiled run ends with a segmentation stage (its segments are " +
                      "joined across tiles); the last stage here is '" +
                      (config.stages.empty() ? "none" : config.stages.back().type) + "'");
  if (!config.output.cloud.empty())
    throw ConfigError(why + "output.cloud is not written by a tiled run; set it to ''");
  const std::string unjoined = joined->unjoinedOutput();
  if (!unjoined.empty())
    throw ConfigError(why + config.stages.back().tag + "." + unjoined +
                      " is not written by a tiled run (its files are not joined across tiles); "
                      "leave it unset");
  const std::string setting = joined->unjoinedSetting();
  if (!setting.empty())
    throw ConfigError(why + config.stages.back().tag + "." + setting +
                      " is not for a tiled run (kinematic segments are not joined across tiles "
                      "yet); run untiled or leave it at primitives");
  return *joined;
}

/// A sampling stage's `points` is a budget for the whole cloud. In voxel mode the tiles all use
/// the leaf the untiled run would choose (voxelLeafForTarget, each tile counting the voxels whose
/// corner lies in its core: the counts add up to the whole cloud's) and its grid's origin, so
/// that every tile is analysed at the untiled run's voxels; in random mode each tile gets its
/// share of the budget. A given `leaf` is kept as it is.
struct TileSampling {
  std::size_t stage = 0;  ///< its place in the pipeline
  std::string tag;
  std::optional<double> leaf;             ///< every tile's, when chosen here
  std::optional<Eigen::Vector3d> origin;  ///< every tile's, when chosen here
  std::optional<std::size_t> points;      ///< every tile's, when chosen here
  std::optional<double> share_of;         ///< random mode: the whole cloud's budget, shared

  /// The stage's sampling in a tile of \a tile_points of \a cloud_points.
  SubsampleParameters forTile(SubsampleParameters p, std::uint64_t tile_points,
                              std::uint64_t cloud_points) const {
    if (leaf)
      p.leaf = leaf;
    if (origin)
      p.origin = origin;
    if (points)
      p.points = *points;
    if (share_of) {
      const double share = *share_of * static_cast<double>(tile_points) /
                           static_cast<double>(std::max<std::uint64_t>(cloud_points, 1));
      p.points = static_cast<std::size_t>(std::max(100.0, std::ceil(share)));
    }
    return p;
  }
  /// The report's words for what every tile is given ("sample.leaf=0.0157183"), one a line.
  std::vector<std::string> described() const {
    std::vector<std::string> lines;
    std::ostringstream o;
    if (origin) {
      o << std::setprecision(17) << tag << ".origin=[" << origin->x() << ", " << origin->y() << ", "
        << origin->z() << "]";
      lines.push_back(o.str());
    }
    if (leaf) {
      o.str("");
      o << std::setprecision(17) << tag << ".leaf=" << *leaf;
      lines.push_back(o.str());
    }
    if (points)
      lines.push_back(tag + ".points=" + std::to_string(*points));
    return lines;
  }
};

/// The sampling stages of \a config (SampledAnalysis), each with what the tiles are given. With
/// \a count false, only what needs no count of the tiles' voxels (the random mode's shares).
std::vector<TileSampling> tileSamplings(const PipelineConfig& config,
                                        const TilingManifest& manifest, const TileTree& tree,
                                        const std::string& tiles_dir, bool count,
                                        WorkDistribution* work = nullptr) {
  std::vector<TileSampling> samplings;
  for (std::size_t k = 0; k < config.stages.size(); ++k) {
    const auto* sampled = dynamic_cast<const SampledAnalysis*>(config.stages[k].stage.get());
    if (!sampled)
      continue;
    const SubsampleParameters& p = sampled->sampling();
    TileSampling t;
    t.stage = k;
    t.tag = config.stages[k].tag;
    const double whole = static_cast<double>(p.points);
    if (p.mode != SubsampleMode::voxel) {
      if (!p.leaf)
        t.share_of = whole;
      samplings.push_back(t);
      continue;
    }
    if (!count) {
      samplings.push_back(t);
      continue;
    }
    // The untiled run's grid: its lowest corner as the voxels' origin, unless one is given.
    const Eigen::Vector3d origin(manifest.lo[0], manifest.lo[1], manifest.lo[2]);
    if (!p.origin)
      t.origin = origin;
    if (p.leaf || whole >= static_cast<double>(manifest.points)) {
      if (!p.leaf)
        t.points = manifest.points;  // untiled, every point is analysed: so in every tile
      samplings.push_back(t);
      continue;  // a given leaf is every tile's
    }
    // The untiled run's leaf search: its box (sizes in float, as the stage sees float coordinates).
    Eigen::Vector3d sizes;
    for (int a = 0; a < 3; ++a)
      sizes[a] = static_cast<double>(static_cast<float>(manifest.hi[a]) -
                                     static_cast<float>(manifest.lo[a]));
    // Shared among the ranks (with \a work: a collective call): each counts its tiles' voxels
    // and the counts are added up, so that every rank searches alike. A rank that cannot read
    // its tiles counts none and says so after the search.
    std::string failure;
    const int rank = work ? work->rank() : 0, ranks = work ? work->ranks() : 1;
    t.leaf = voxelLeafForTarget(sizes, p.points, [&](double l) {
      std::size_t n = 0;
      for (std::size_t k = static_cast<std::size_t>(rank);
           k < manifest.tiles.size() && failure.empty(); k += static_cast<std::size_t>(ranks)) {
        const TileInfo& tile = manifest.tiles[k];
        try {
          CloudStream in(tiles_dir + "/" + tile.name() + ".ply");
          Eigen::Matrix3Xd xyz;
          in.read(0, in.size(), xyz);
          n += occupiedVoxels(xyz, l, origin, [&](const Eigen::Vector3d& corner) {
            return tree.owner(corner.x(), corner.y()) == tile.key;
          });
        } catch (const std::exception& e) {
          if (ranks == 1)
            throw;
          failure = e.what();
        }
      }
      return work ? work->sum(n) : n;
    });
    if (work)
      work->shareFailure(failure);
    samplings.push_back(t);
  }
  return samplings;
}

/// The tiles' samplings as a cache file (the leaf search reads every tile a few times).
std::string samplingsText(const std::vector<TileSampling>& samplings) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginSeq;
  for (const TileSampling& t : samplings) {
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "stage" << YAML::Value << t.stage;
    if (t.leaf)
      out << YAML::Key << "leaf" << YAML::Value << *t.leaf;
    if (t.origin)
      out << YAML::Key << "origin" << YAML::Value << YAML::Flow << YAML::BeginSeq << t.origin->x()
          << t.origin->y() << t.origin->z() << YAML::EndSeq;
    if (t.points)
      out << YAML::Key << "points" << YAML::Value << *t.points;
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  return std::string(out.c_str()) + "\n";
}

/// Reads back what samplingsText wrote into \a samplings (matched by stage).
void readSamplings(const std::string& text, std::vector<TileSampling>& samplings) {
  const YAML::Node list = YAML::Load(text);
  for (const YAML::Node& entry : list)
    for (TileSampling& t : samplings) {
      if (t.stage != entry["stage"].as<std::size_t>())
        continue;
      if (entry["leaf"])
        t.leaf = entry["leaf"].as<double>();
      if (entry["origin"])
        t.origin = Eigen::Vector3d(entry["origin"][0].as<double>(), entry["origin"][1].as<double>(),
                                   entry["origin"][2].as<double>());
      if (entry["points"])
        t.points = entry["points"].as<std::size_t>();
    }
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

/// tiling.workdir, or <output.dir>/tiles.
std::string workDirectoryPath(const PipelineConfig& config) {
  return config.tiling.workdir.empty() ? config.output.dir + "/tiles" : config.tiling.workdir;
}

/// What each rank must agree on with the leader: the config as the tiles run it and the tiling
/// (the work directory is compared by its token, which a directory of the same name on another
/// node does not hold).
std::string configDigest(const PipelineConfig& config) {
  std::ostringstream text;
  text << std::setprecision(17) << effectiveConfig(config) << config.input.path << "\n";
  if (config.tiling.size)
    text << *config.tiling.size << " " << config.tiling.bufferWidth(*config.tiling.size);
  else
    text << "auto " << config.tiling.buffer;
  text << " " << config.tiling.max_points << "\n";
  return detail::hex(detail::digest(text.str()));
}

/// The report's line on the tiles' capacity: the limit, and the tiles split to hold it (and any
/// that still exceed it, at the smallest edge the buffer allows).
std::string splitsText(const TilingManifest& m) {
  std::ostringstream text;
  text << "tiling: at most ";
  if (m.max_points == 0) {
    text << "any number of points a tile (tiling.max_points 0)\n";
    return text.str();
  }
  text << m.max_points << " points in a tile's core (tiling.max_points)";
  int deepest = 0;
  std::size_t quarters = 0, over = 0;
  std::uint64_t most = 0;
  for (const TileInfo& t : m.tiles) {
    deepest = std::max(deepest, t.key.level);
    quarters += t.key.level > 0 ? 1 : 0;
    over += t.core > m.max_points ? 1 : 0;
    most = std::max(most, t.core);
  }
  if (quarters > 0)
    text << ": " << quarters << " tiles are quarters of denser ones, down to an edge of "
         << std::ldexp(m.size, -deepest);
  text << "; the fullest holds " << most;
  if (over > 0)
    text << " (" << over << " over the limit: their quarters would be narrower than twice the "
         << "buffer " << m.buffer << ")";
  text << "\n";
  return text.str();
}

/// The report's lines on where a tiled run's time went: the phases its ranks shared, and those
/// that more ranks do not shorten (the leader's alone while the others wait, or work every rank
/// does alike), with their share of the run.
std::string timingText(const std::vector<std::pair<std::string, double>>& shared,
                       const std::vector<std::pair<std::string, double>>& serial, int ranks,
                       double total) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(2) << "timing: shared by " << ranks
       << (ranks == 1 ? " process" : " ranks") << ":";
  for (std::size_t k = 0; k < shared.size(); ++k)
    text << (k ? ", " : " ") << shared[k].first << " " << shared[k].second << " s";
  double alone = 0.0;
  for (const auto& [name, s] : serial)
    alone += s;
  text << "\n  not shared: " << alone << " s of " << total << " s (" << std::setprecision(1)
       << 100.0 * alone / std::max(total, 1e-9) << " %)" << std::setprecision(2) << ":";
  for (std::size_t k = 0; k < serial.size(); ++k)
    text << (k ? ", " : " ") << serial[k].first << " " << serial[k].second << " s";
  text << "\n";
  return text.str();
}

}  // namespace

void checkTiledRun(const PipelineConfig& config) {
  joinedStage(config);
  checkWorkDirectory(workDirectoryPath(config), config.input.path);
}

std::vector<std::string> runTiled(const PipelineConfig& config,
                                  const std::vector<std::string>& overrides,
                                  const RunOptions& options, std::ostream& report_stream) {
  JoinedAcrossTiles& joined = joinedStage(config);
  checkConfigFiles(config);
  WorkDistribution work;  // one process, or the ranks of mpirun
  detail::NullBuffer null_buffer;
  std::ostream null_stream(&null_buffer);
  std::ostream& report = options.quiet || !work.leader() ? null_stream : report_stream;
  Progress progress(!options.quiet && work.leader());

  const std::string dir = workDirectoryPath(config);
  std::optional<WorkDirectory> claimed;  // the leader's, locked until the run ends
  const std::string tiles_dir = dir + "/tiles", runs_dir = dir + "/runs";
  const std::string manifest_path = dir + "/manifest.yaml";
  const auto start = std::chrono::steady_clock::now();
  const auto seconds = [](auto since) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
  };

  // Where the time goes: phases the ranks share, and phases that do not get shorter with more
  // ranks (the leader's alone, while the others wait; or work every rank does alike).
  std::vector<std::pair<std::string, double>> shared, serial;
  auto step_start = std::chrono::steady_clock::now();

  // 1. Tiles: reused when the manifest is of this input and tiling, else written anew by all the
  // ranks, each its share of the input's rows.
  TilingManifest manifest;
  std::string failure;
  if (work.leader()) {
    try {
      claimed.emplace(dir, config.input.path);
      for (const std::string& done : removeLeftovers(config.output.dir, config.input.path))
        report << "output: " << done << ", left by a killed run\n";
    } catch (const std::exception& e) {
      failure = e.what();
    }
  }
  work.shareFailure(failure);
  // Every rank sees the leader's work directory (its token) and runs the leader's config.
  const std::string token = work.broadcast(claimed ? claimed->token() : "");
  const std::string leader_config = work.broadcast(configDigest(config));
  failure.clear();
  if (readRunToken(dir) != token)
    failure = "tiling.workdir '" + dir +
              "' is not the one the first rank claimed: the ranks must share one work directory";
  else if (configDigest(config) != leader_config)
    failure =
        "this rank's config differs from the first rank's: every rank must run the same "
        "config and --set options";
  work.shareFailure(failure);
  serial.emplace_back("work directory", seconds(step_start));
  double size = config.tiling.size.value_or(0.0);
  step_start = std::chrono::steady_clock::now();
  if (!config.tiling.size) {
    progress.begin(1, 3, "size the tiles of " + config.input.path);
    const std::uint64_t target =
        config.tiling.max_points > 0 ? config.tiling.max_points : TilingSection::kDefaultMaxPoints;
    const AutoTileSize a =
        autoTileSize(config.input.path, config.input.nan, target, config.tiling.buffer, {}, &work);
    progress.end();
    size = a.size;
    report << "tiling: size auto: " << a.size << " (" << a.points << " points over " << a.width
           << " x " << a.depth << " in x and y: a tile of their mean density "
           << "holds about " << a.target << ")\n";
    shared.emplace_back("tile size", seconds(step_start));
  }
  const TileGrid grid(size, config.tiling.bufferWidth(size));
  step_start = std::chrono::steady_clock::now();
  std::string reuse;  // the leader's verdict on the tiles: "1" reuse them, "0" tile anew
  if (work.leader()) {
    try {
      TilingManifest old;
      std::uint64_t bytes = 0;
      std::int64_t mtime = 0;
      inputStamp(config.input.path, bytes, mtime);
      if (readManifest(manifest_path, old) && old.input == config.input.path &&
          old.input_bytes == bytes && old.input_mtime == mtime && old.size == grid.size() &&
          old.buffer == grid.buffer() && old.max_points == config.tiling.max_points) {
        const std::string why = verifyTiles(old, tiles_dir);
        if (why.empty()) {
          manifest = old;
          report << "tiling: reusing " << manifest.tiles.size() << " tiles in " << tiles_dir
                 << "\n";
        } else {
          report << "tiling: " << why << "; tiling anew\n";
        }
      }
      if (manifest.tiles.empty())
        claimed->removeTiling();
    } catch (const std::exception& e) {
      failure = e.what();
    }
    reuse = manifest.tiles.empty() ? "0" : "1";
  }
  const bool anew = work.broadcast(reuse) == "0";
  work.shareFailure(failure);
  serial.emplace_back("reuse check", seconds(step_start));
  const auto tiling_start = std::chrono::steady_clock::now();
  if (anew) {
    progress.begin(1, 3, "tile " + config.input.path);
    manifest = writeTiles(
        config.input.path, config.input.nan, grid, config.tiling.max_points, tiles_dir,
        [](std::uint64_t, std::uint64_t) {}, &work);
    progress.end();
    shared.emplace_back("tiling", seconds(tiling_start));
    step_start = std::chrono::steady_clock::now();
    if (work.leader()) {
      try {
        writeAtomically(manifest_path, manifestText(manifest));
      } catch (const std::exception& e) {
        failure = e.what();
      }
      report << "tiling: " << manifest.points << " points";
      if (manifest.dropped)
        report << " (" << manifest.dropped << " with a non-finite coordinate dropped)";
      report << " into " << manifest.tiles.size() << " tiles of " << grid.size() << " (buffer "
             << grid.buffer() << ") in " << tiles_dir << ", " << std::fixed << std::setprecision(2)
             << seconds(tiling_start) << " s on " << work.ranks()
             << (work.ranks() == 1 ? " process" : " ranks") << "\n"
             << std::defaultfloat;
      report << splitsText(manifest);
    }
  }
  work.shareFailure(failure);
  if (anew)
    serial.emplace_back("manifest", seconds(step_start));
  if (!work.leader() && manifest.tiles.empty() && !readManifest(manifest_path, manifest))
    failure = "'" + manifest_path + "': cannot be read on this rank";
  work.shareFailure(failure);

  // The analysis density of the untiled run, in every tile: counted by all the ranks, each its
  // share of the tiles, unless an earlier run of this config on these tiles counted it.
  auto phase_start = std::chrono::steady_clock::now();
  std::vector<TileSampling> samplings;
  std::string fingerprint = effectiveConfig(config);
  // The leaf search reads every tile a few times: its result is kept for reruns of this config
  // on these tiles (the file goes with the tiles when they are written anew).
  const std::string cache = dir + "/analysis", key = fingerprint + "\n--\nsamplings 2\n";
  std::string text;  // the leader's: "1" and the cached samplings, or "0"
  failure.clear();
  if (work.leader()) {
    text = readText(cache);
    bool cached = false;
    if (text.rfind(key, 0) == 0) {
      try {
        text = text.substr(key.size());
        samplings = tileSamplings(config, manifest, manifest.tree(), tiles_dir, false);
        readSamplings(text, samplings);
        cached = true;
      } catch (const YAML::Exception&) {
        // a damaged cache: counted again below
      }
    }
    text = cached ? "1" + text : "0";
  }
  text = work.broadcast(text);
  serial.emplace_back("analysis cache", seconds(phase_start));
  phase_start = std::chrono::steady_clock::now();
  if (text[0] == '0') {
    samplings = tileSamplings(config, manifest, manifest.tree(), tiles_dir, true, &work);
    text = samplingsText(samplings);
    shared.emplace_back("analysis", seconds(phase_start));
  } else {
    text = text.substr(1);
  }
  phase_start = std::chrono::steady_clock::now();
  if (work.leader()) {
    try {
      writeAtomically(cache, key + text);
      // Runs of another config (or another analysis density) are not reused, nor those of a
      // build whose tiles sampled the noise otherwise.
      fingerprint += "\n" + text + "noise sampled by the tile's share\n";
      fs::create_directories(runs_dir);
      if (readText(runs_dir + "/config") != fingerprint) {
        claimed->removeRuns();
        fs::create_directories(runs_dir);
        writeAtomically(runs_dir + "/config", fingerprint);
      }
      writeAtomically(runs_dir + "/analysis", text);
      for (const TileSampling& t : samplings)
        for (const std::string& line : t.described())
          report << "tiling: every tile analysed with " << line << " (as untiled)\n";
    } catch (const std::exception& e) {
      failure = e.what();
    }
  }
  work.shareFailure(failure);
  if (samplings.empty() || !work.leader()) {  // the leader's choice, read back (no second count)
    samplings = tileSamplings(config, manifest, manifest.tree(), tiles_dir, false);
    readSamplings(text, samplings);
  }
  serial.emplace_back("analysis files", seconds(phase_start));

  // 2. The tiles' runs: the unchanged pipeline on each tile, its report in the tile's directory.
  // Tiles are independent: a process runs as many at a time as it has threads, each tile on one
  // thread (more than one when fewer tiles than threads are left). Whole tiles in parallel use
  // the cores better than one tile's stages do, and the outputs do not depend on the threads.
  const auto tiles_start = std::chrono::steady_clock::now();
  // Which tile runs verify ('1': done): each rank reads and digests its share of the tiles, and
  // what they found is shared, not read once by every rank and again by the worker that takes
  // the tile.
  std::string verified(manifest.tiles.size(), '0');
  {
    std::string mine;
    work.together([&] {
      for (std::size_t t = static_cast<std::size_t>(work.rank()); t < manifest.tiles.size();
           t += static_cast<std::size_t>(work.ranks())) {
        std::string why;
        const bool done = tileDone(runs_dir + "/" + manifest.tiles[t].name(), why);
        mine += done ? '1' : '0';
        packText(mine, done ? "" : why);
      }
    });
    const std::vector<std::string> all = work.allGather(mine);
    for (std::size_t r = 0; r < all.size(); ++r) {
      Unpack in(all[r]);
      for (std::size_t t = r; t < manifest.tiles.size(); t += all.size()) {
        verified[t] = in.next<char>();
        const std::string why = in.text();
        if (!why.empty())
          report << "tiling: " << manifest.tiles[t].name() << "'s run does not verify (" << why
                 << "); running it again\n";
      }
    }
  }
  shared.emplace_back("verifying tile runs", seconds(tiles_start));
  const auto runs_start = std::chrono::steady_clock::now();
  const auto to_run = static_cast<std::size_t>(std::count(verified.begin(), verified.end(), '0'));
  const int threads = resolveThreads(config.settings.threads);
  const int workers =
      static_cast<int>(std::max<std::size_t>(1, std::min<std::size_t>(threads, to_run)));
  const int tile_threads = std::max(1, threads / workers);
  const JoinedAcrossTiles::Files files = joined.joinedFiles();
  const std::string report_name = files.report, segments_name = files.segments;
  std::atomic<std::size_t> ran{0};
  std::mutex progress_mutex;
  failure.clear();
  try {
    work.forEachTile(manifest.tiles.size(), workers, [&](std::size_t t) {
      const TileInfo& tile = manifest.tiles[t];
      const std::string run_dir = runs_dir + "/" + tile.name();
      if (verified[t] == '1')
        return;
      const auto tile_start = std::chrono::steady_clock::now();
      // The pipeline as configured (the user's overrides included), on the tile: its input and
      // output, no output cloud, no picture, its share of the threads, the untiled sampling.
      PipelineConfig tile_config = loadConfig(config.path, overrides);
      tile_config.input.path = tiles_dir + "/" + tile.name() + ".ply";
      tile_config.input.sensor = manifest.sensor;  // a tile of a sensor's view is one too
      tile_config.output.dir = run_dir;
      tile_config.output.cloud.clear();
      tile_config.tiling.size = 0.0;
      tile_config.settings.threads = tile_threads;
      dynamic_cast<JoinedAcrossTiles&>(*tile_config.stages.back().stage)
          .forTile(
              std::min(1.0, static_cast<double>(tile.points) /
                                static_cast<double>(std::max<std::uint64_t>(manifest.points, 1))));
      for (const TileSampling& sampling : samplings) {
        auto& stage = dynamic_cast<SampledAnalysis&>(*tile_config.stages[sampling.stage].stage);
        stage.setSampling(sampling.forTile(stage.sampling(), tile.points, manifest.points));
      }
      RunOptions quiet;
      quiet.quiet = true;
      quiet.final_outputs = false;  // a tile's outputs are not the run's
      try {
        runPipeline(tile_config, quiet, null_stream);
        summariseTile(run_dir, segments_name, report_name);
      } catch (const RunError& e) {
        throw RunError("tile " + tile.name() + ": " + e.what());
      } catch (const std::bad_alloc&) {  // reading the tile, writing its outputs, summarising
        throw RunError("tile " + tile.name() + ": out of memory (" + std::to_string(tile.points) +
                       " points; a smaller tiling.max_points " + "bounds a tile's points)");
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
  shared.emplace_back("tile runs", seconds(runs_start));
  report << "tiling: " << ran_total << " tiles run, " << manifest.tiles.size() - ran_total
         << " already done, " << std::fixed << std::setprecision(2) << seconds(runs_start) << " s\n"
         << std::defaultfloat;

  // 3. The merge, shared among the ranks (tile_merge.h); the leader writes the outputs.
  std::vector<std::string> written;
  const auto merge_start = std::chrono::steady_clock::now();
  progress.begin(3, 3, "merge " + std::to_string(manifest.tiles.size()) + " tiles");
  std::optional<OutputFiles> outputs;
  if (work.leader()) {
    outputs.emplace(config.output.dir);
    outputs->protect(config.input.path);
  }
  const std::optional<RenderRequest> render = joined.picture();
  MergeTimes merge_times;
  const MergeSummary s =
      mergeTiles(manifest, tiles_dir, runs_dir, files, render ? &*render : nullptr, threads,
                 outputs ? &*outputs : nullptr, work, &merge_times);
  const auto commit_start = std::chrono::steady_clock::now();
  if (work.leader()) {
    try {
      written = outputs->commit();
    } catch (const std::exception& e) {
      failure = e.what();
    }
  }
  work.shareFailure(failure);
  progress.end();
  serial.emplace_back("merge: numbering", merge_times.segments);
  serial.emplace_back("merge: outputs", merge_times.leader + seconds(commit_start));
  shared.emplace_back("merge", seconds(merge_start) - merge_times.segments - merge_times.leader -
                                   seconds(commit_start));
  report << "segmentation: " << s.segments << " segments from " << s.pieces << " tile segments ("
         << s.joins << " joins across tiles), " << s.assigned << "/" << s.points
         << " points assigned\n";
  report << "  merge: " << std::fixed << std::setprecision(2) << seconds(merge_start)
         << " s, whole run " << seconds(start) << " s\n"
         << std::defaultfloat;
  report << timingText(shared, serial, work.ranks(), seconds(start));
  for (const auto& path : written)
    report << "wrote " << path << "\n";
  return written;
}

}  // namespace slipfit::pipeline
