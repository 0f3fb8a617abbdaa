#include "tiler.h"

#include "packed_values.h"
#include "ply_rows.h"

#include "slipfit/pipeline/cloud_stream.h"
#include "slipfit/pipeline/errors.h"
#include "slipfit/tiling/tile_tree.h"

#include <yaml-cpp/yaml.h>

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

namespace slipfit::pipeline::tiling {

namespace {

constexpr std::uint64_t kRowsPerChunk = 1u << 16;
constexpr std::size_t kBufferedBytes = std::size_t{32} << 20;  // all tiles' write buffers
/// The levels of quarters a pass counts below an over-full tile (4^3 = 64 cells each).
constexpr int kSplitLevels = 3;

/// The input's coordinates of each row of a chunk.
struct Coordinates {
  FieldAt x, y, z;
  void at(const char* row, double& px, double& py, double& pz) const {
    px = x.get(row);
    py = y.get(row);
    pz = z.get(row);
  }
};

Coordinates coordinatesOf(const std::vector<StreamField>& fields) {
  return {fieldAt(*findField(fields, "x")), fieldAt(*findField(fields, "y")),
          fieldAt(*findField(fields, "z"))};
}

/// Reads rows [\a begin, \a end) of \a in in chunks; \a visit(row index, row bytes, x, y, z) for
/// rows with finite coordinates; counts the others (or throws under NanPolicy::error).
template <typename Visit>
std::uint64_t forEachRow(CloudStream& in, const std::string& path, NanPolicy nan,
                         std::uint64_t begin, std::uint64_t end, Visit&& visit,
                         const std::function<void(std::uint64_t, std::uint64_t)>& progress,
                         std::uint64_t done_before, std::uint64_t total) {
  const Coordinates c = coordinatesOf(in.fields());
  std::vector<char> rows;
  std::uint64_t dropped = 0;
  for (std::uint64_t first = begin; first < end; first += kRowsPerChunk) {
    const std::uint64_t n = std::min(kRowsPerChunk, end - first);
    in.readRecords(first, n, rows);
    for (std::uint64_t r = 0; r < n; ++r) {
      const char* row = rows.data() + r * in.recordBytes();
      double x, y, z;
      c.at(row, x, y, z);
      if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
        if (nan == NanPolicy::error)
          throw RunError("input '" + path + "': point " + std::to_string(first + r) +
                         " has a non-finite coordinate; set input.nan: skip to drop such points");
        ++dropped;
        continue;
      }
      visit(first + r, row, x, y, z);
    }
    if (progress)
      progress(done_before + first + n - begin, total);
  }
  return dropped;
}

/// The processes that read an input together (a WorkDistribution's ranks, or this one alone):
/// each reads its share of the rows, a contiguous range in the input's order, and what they
/// count is added up in rank order. A failure on any rank is every rank's (no rank is left
/// waiting for the others).
class RowShare {
 public:
  RowShare(WorkDistribution* work, std::uint64_t rows) : work_(work) {
    const auto r = static_cast<std::uint64_t>(work ? work->rank() : 0);
    const auto n = static_cast<std::uint64_t>(work ? work->ranks() : 1);
    // rows r·S/R without overflow for any S < 2^64 / R
    begin = rows / n * r + rows % n * r / n;
    end = rows / n * (r + 1) + rows % n * (r + 1) / n;
  }
  bool alone() const { return !work_ || work_->ranks() == 1; }
  /// Runs \a local here and shares its failure (RunError on every rank when any rank's threw).
  template <typename Local>
  void run(Local&& local) {
    if (alone())
      local();
    else
      work_->together(local);
  }
  /// Every rank's \a bytes, in rank order.
  std::vector<std::string> gather(const std::string& bytes) {
    return alone() ? std::vector<std::string>{bytes} : work_->allGather(bytes);
  }
  std::vector<std::uint64_t> sumBefore(const std::vector<std::uint64_t>& values) {
    return alone() ? std::vector<std::uint64_t>(values.size(), 0) : work_->sumBefore(values);
  }
  std::uint64_t begin = 0, end = 0;  ///< this rank's rows

 private:
  WorkDistribution* work_;
};

/// A map of tile keys to counts as bytes, and the sum of several such maps.
template <typename Count>
std::string packCounts(const std::map<TileKey, Count>& counts) {
  std::string bytes;
  for (const auto& [key, count] : counts) {
    pack(bytes, key.i);
    pack(bytes, key.j);
    pack(bytes, key.level);
    pack(bytes, count);
  }
  return bytes;
}
/// Reads what packCounts wrote from \a in, up to its end.
template <typename Count, typename Add>
void addCounts(Unpack& in, std::map<TileKey, Count>& counts, Add&& add) {
  while (!in.done()) {
    TileKey key;
    key.i = in.next<std::int64_t>();
    key.j = in.next<std::int64_t>();
    key.level = in.next<int>();
    add(key, counts[key], in.next<Count>());
  }
}

/// One tile's file while it is written: rows wait in a buffer and are written in batches at
/// their place (this rank's rows follow those of the ranks before it), so that no more than one
/// file is open at a time.
struct TileWriter {
  std::string path, header;
  std::uint64_t next = 0;  ///< the byte the next row goes to
  std::vector<char> pending;
  void flush() {
    if (pending.empty())
      return;
    PositionalFile file(path);
    file.write(next, pending.data(), pending.size());
    file.close();
    next += pending.size();
    pending.clear();
    pending.shrink_to_fit();
  }
};

}  // namespace

void inputStamp(const std::string& path, std::uint64_t& bytes, std::int64_t& mtime) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0)
    throw RunError("input '" + path + "': cannot be read");
  bytes = static_cast<std::uint64_t>(st.st_size);
  mtime = static_cast<std::int64_t>(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec;
}

double roundUpToOneTwoFive(double edge) {
  if (!(edge > 0.0) || !std::isfinite(edge))
    return edge;
  const double decade = std::pow(10.0, std::floor(std::log10(edge)));
  for (const double step : {1.0, 2.0, 5.0, 10.0})
    if (step * decade >= edge)
      return step * decade;
  return 10.0 * decade;  // log10's rounding put edge a hair above 10 × decade
}

AutoTileSize autoTileSize(const std::string& input, NanPolicy nan, std::uint64_t target,
                          double buffer,
                          const std::function<void(std::uint64_t, std::uint64_t)>& progress,
                          WorkDistribution* work) {
  std::optional<CloudStream> in;
  double lo[2] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  double hi[2] = {-lo[0], -lo[1]};
  AutoTileSize a;
  std::uint64_t rows = 0;
  RowShare share(work, 0);
  share.run([&] {
    in.emplace(input);
    rows = in->size();
  });
  share = RowShare(work, rows);
  share.run([&] {
    forEachRow(
        *in, input, nan, share.begin, share.end,
        [&](std::uint64_t, const char*, double x, double y, double) {
          lo[0] = std::min(lo[0], x);
          hi[0] = std::max(hi[0], x);
          lo[1] = std::min(lo[1], y);
          hi[1] = std::max(hi[1], y);
          ++a.points;
        },
        progress, 0, share.end - share.begin);
  });
  std::string mine;
  for (const double v : {lo[0], lo[1], hi[0], hi[1]})
    pack(mine, v);
  pack(mine, a.points);
  a.points = 0;
  for (const std::string& theirs : share.gather(mine)) {
    Unpack u(theirs);
    for (double& v : lo)
      v = std::min(v, u.next<double>());
    for (double& v : hi)
      v = std::max(v, u.next<double>());
    a.points += u.next<std::uint64_t>();
  }
  if (a.points == 0)
    throw RunError("input '" + input + "': no point has finite coordinates to tile");
  a.width = hi[0] - lo[0];
  a.depth = hi[1] - lo[1];
  a.target = std::max<std::uint64_t>(target, 1);
  const double share_of_points = static_cast<double>(a.target) / static_cast<double>(a.points);
  // Evenly over the box: e² N / (w d) = target while e is within the shorter side; past it a
  // tile covers e × min(w, d), and e N / max(w, d) = target. The larger of the two is the one
  // that holds.
  const double longer = std::max(a.width, a.depth);
  double edge = std::max(std::sqrt(a.width * a.depth * share_of_points), longer * share_of_points);
  if (buffer > 0.0)
    edge = std::max(edge, 4.0 * buffer);
  if (!(edge > 0.0))  // every point at one x, y: any edge holds them
    edge = buffer > 0.0 ? 4.0 * buffer : 1.0;
  a.size = roundUpToOneTwoFive(edge);
  return a;
}

TilingManifest writeTiles(const std::string& input, NanPolicy nan, const TileGrid& grid,
                          std::uint64_t max_points, const std::string& dir,
                          const std::function<void(std::uint64_t, std::uint64_t)>& progress,
                          WorkDistribution* work) {
  TilingManifest m;
  std::optional<CloudStream> opened;
  RowShare share(work, 0);
  share.run([&] {
    opened.emplace(input);
    for (const StreamField& f : opened->fields())
      if (f.scalar == ply::Scalar::i64 || f.scalar == ply::Scalar::u64)
        throw RunError("input '" + input + "': field " + f.name +
                       " holds 8-byte integers, which PLY tiles cannot carry");
    for (const StreamField& f : opened->fields())
      if (f.name == "tile_row" || f.name == "tile_core")
        throw RunError("input '" + input + "': field " + f.name + " is the tiling's own");
    inputStamp(input, m.input_bytes, m.input_mtime);
  });
  CloudStream& in = *opened;
  share = RowShare(work, in.size());
  m.input = input;
  m.size = grid.size();
  m.buffer = grid.buffer();
  m.max_points = max_points;
  m.double_coordinates = in.doubleCoordinates();
  m.sensor = in.sensor();
  for (int a = 0; a < 3; ++a) {
    m.lo[a] = std::numeric_limits<double>::infinity();
    m.hi[a] = -std::numeric_limits<double>::infinity();
  }

  TileTree tree(grid);
  const auto outside = [&](double x, double y) {
    std::ostringstream why;
    why << std::setprecision(17) << "input '" << input << "': coordinate (" << x << ", " << y
        << ") is more than 2^53 tiles of tiling.size " << grid.size()
        << " from the origin; set a larger tiling.size";
    return RunError(why.str());
  };
  const auto place = [&](double x, double y, const auto& visit) {
    try {
      tree.forEachCovering(x, y, visit);
    } catch (const std::invalid_argument&) {
      throw outside(x, y);
    }
  };
  const auto ownerOf = [&](double x, double y) {
    try {
      return tree.owner(x, y);
    } catch (const std::invalid_argument&) {
      throw outside(x, y);
    }
  };
  // The passes read this rank's rows once each: the progress total grows with the passes.
  const std::uint64_t mine = share.end - share.begin;
  std::uint64_t passes_done = 0, passes_planned = 2;
  const auto pass = [&](const auto& visit) {
    std::uint64_t dropped = 0;
    share.run([&] {
      dropped = forEachRow(in, input, nan, share.begin, share.end, visit, progress,
                           passes_done * mine, passes_planned * mine);
    });
    ++passes_done;
    return dropped;
  };

  // Pass 1: each tile's points and core points (no more than kMostTiles are counted: past them,
  // only the extent, for the message); counted again on the leaves when tiles are split. Each
  // rank counts its rows; the counts are added up (`local`: this rank's, for its place in the
  // tile files).
  std::map<TileKey, TileInfo> tiles, local;
  std::uint64_t local_points = 0;  // this rank's rows with finite coordinates
  bool too_many = false;
  const auto countTiles = [&](bool extent) {
    local.clear();
    bool local_too_many = false;
    std::uint64_t& points = local_points;
    points = 0;
    const std::uint64_t dropped =
        pass([&](std::uint64_t, const char*, double x, double y, double z) {
          if (extent) {
            const double p[3] = {x, y, z};
            for (int a = 0; a < 3; ++a) {
              m.lo[a] = std::min(m.lo[a], p[a]);
              m.hi[a] = std::max(m.hi[a], p[a]);
            }
          }
          ++points;
          if (local_too_many)
            return;
          const TileKey own = ownerOf(x, y);
          place(x, y, [&](TileKey t) {
            TileInfo& info = local[t];
            info.key = t;
            ++info.points;
            if (t == own)
              ++info.core;
          });
          local_too_many = local.size() > 4 * kMostTiles;  // buffer-only tiles are not written
        });
    std::string bytes;
    for (int a = 0; a < 3; ++a) {
      pack(bytes, m.lo[a]);
      pack(bytes, m.hi[a]);
    }
    pack(bytes, points);
    pack(bytes, dropped);
    pack(bytes, local_too_many);
    bytes += packCounts(local);
    tiles.clear();
    too_many = false;
    std::uint64_t all_points = 0, all_dropped = 0;
    for (const std::string& theirs : share.gather(bytes)) {
      Unpack u(theirs);
      for (int a = 0; a < 3; ++a) {
        m.lo[a] = std::min(m.lo[a], u.next<double>());
        m.hi[a] = std::max(m.hi[a], u.next<double>());
      }
      all_points += u.next<std::uint64_t>();
      all_dropped += u.next<std::uint64_t>();
      too_many = u.next<bool>() || too_many;
      addCounts(u, tiles, [](const TileKey&, TileInfo& sum, const TileInfo& add) {
        sum.key = add.key;
        sum.points += add.points;
        sum.core += add.core;
      });
    }
    too_many = too_many || tiles.size() > 4 * kMostTiles;
    if (extent)
      m.points = all_points;
    return all_dropped;
  };
  m.dropped = countTiles(true);
  if (m.points == 0)
    throw RunError("input '" + input + "': no point with finite coordinates");

  // Tiles whose cores hold more than max_points are split into quarters, and those again, as long
  // as their quarters stay wider than twice the buffer: each further pass counts the cores of an
  // over-full tile's descendants kSplitLevels levels down and splits as deep as they need.
  if (max_points > 0 && !too_many) {
    std::map<TileKey, std::uint64_t> over;  // leaves to split, with their core points
    for (const auto& [key, info] : tiles)
      if (info.core > max_points && tree.splittable(key))
        over[key] = info.core;
    bool split = false;
    while (!over.empty()) {
      // The deepest level each over-full leaf's descendants are counted at.
      const auto deepest = [&](const TileKey& t) {
        TileKey d = t;
        while (d.level < t.level + kSplitLevels && tree.splittable(d))
          d = TileTree::quarters(d)[0];
        return d.level;
      };
      std::map<TileKey, std::uint64_t> counted;  // every descendant's core points, this rank's
      ++passes_planned;
      pass([&](std::uint64_t, const char*, double x, double y, double) {
        TileKey t = ownerOf(x, y);
        if (over.count(t) == 0)
          return;
        for (const int to = deepest(t); t.level < to;) {
          t = tree.quarterOf(t, x, y);
          ++counted[t];
        }
      });
      std::map<TileKey, std::uint64_t> cores;
      for (const std::string& theirs : share.gather(packCounts(counted))) {
        Unpack u(theirs);
        addCounts(u, cores,
                  [](const TileKey&, std::uint64_t& sum, std::uint64_t add) { sum += add; });
      }
      std::map<TileKey, std::uint64_t> next;
      for (const auto& [leaf, points] : over) {
        const int to = deepest(leaf);
        std::vector<std::pair<TileKey, std::uint64_t>> todo{{leaf, points}};
        while (!todo.empty()) {
          const auto [t, n] = todo.back();
          todo.pop_back();
          if (n <= max_points || !tree.splittable(t))
            continue;
          if (t.level == to) {
            next[t] = n;  // counted again one pass further down
            continue;
          }
          tree.split(t);
          split = true;
          for (const TileKey& q : TileTree::quarters(t)) {
            const auto c = cores.find(q);
            todo.emplace_back(q, c == cores.end() ? 0 : c->second);
          }
        }
      }
      over = std::move(next);
    }
    if (split) {
      ++passes_planned;
      countTiles(false);
    }
  }
  const std::size_t written = static_cast<std::size_t>(
      std::count_if(tiles.begin(), tiles.end(), [](const auto& t) { return t.second.core > 0; }));
  if (too_many || written > kMostTiles ||
      static_cast<double>(m.points) < kFewestMeanTilePoints * static_cast<double>(written)) {
    std::ostringstream why;
    why << "input '" << input << "': tiles of size " << grid.size() << " over its extent "
        << m.hi[0] - m.lo[0] << " x " << m.hi[1] - m.lo[1] << " make ";
    if (too_many || written > kMostTiles)
      why << (too_many ? "more than " + std::to_string(4 * kMostTiles) : std::to_string(written))
          << " tiles, over the limit of " << kMostTiles;
    else
      why << written << " tiles of " << static_cast<double>(m.points) / written
          << " points on average, under the " << kFewestMeanTilePoints
          << " a tile needs to be segmented";
    why << "; set a larger tiling.size";
    throw RunError(why.str());
  }

  // Pass 2: the rows of each tile, its fields plus tile_row and tile_core. Every rank writes its
  // rows of each tile at the place the ranks before it leave (their counts of the tile's rows),
  // so the tiles hold their rows in the input's order, as one process writes them.
  std::vector<StreamField> fields = withoutFields(in.fields(), {"_"});  // PCD padding
  const std::uint64_t kept_bytes = fields.empty() ? 0 : fields.back().offset + fields.back().bytes;
  fields.push_back({"tile_row", ply::Scalar::f64, 8, kept_bytes});
  fields.push_back({"tile_core", ply::Scalar::u8, 1, kept_bytes + 8});
  const std::uint64_t tile_row_bytes = kept_bytes + 9;

  std::map<TileKey, TileWriter> writers;
  std::vector<std::uint64_t> mine_counts;  // this rank's rows of each tile, and its finite rows
  for (auto& [key, info] : tiles) {
    if (info.core == 0)
      continue;  // a tile of buffer points only: its neighbours own them all
    TileWriter& w = writers[key];
    w.path = dir + "/" + info.name() + ".ply";
    w.header = plyHeader(fields, info.points);
    m.tiles.push_back(info);
    const auto here = local.find(key);
    mine_counts.push_back(here == local.end() ? 0 : here->second.points);
  }
  mine_counts.push_back(local_points);
  const std::vector<std::uint64_t> before = share.sumBefore(mine_counts);
  {
    std::size_t k = 0;
    for (auto& [key, w] : writers)
      w.next = w.header.size() + before[k++] * tile_row_bytes;
  }
  // The tile files, created with their headers by the ranks in turn.
  share.run([&] {
    std::filesystem::create_directories(dir);
    std::size_t k = 0;
    const int rank = work ? work->rank() : 0, ranks = work ? work->ranks() : 1;
    for (const auto& [key, w] : writers)
      if (static_cast<int>(k++ % static_cast<std::size_t>(ranks)) == rank) {
        std::ofstream out(w.path, std::ios::binary | std::ios::trunc);
        if (!out)
          throw RunError("tile '" + w.path + "': cannot be created");
        writeOrFail(out, w.header.data(), w.header.size(), w.path);
        out.close();
        if (!out)
          throw RunError("'" + w.path + "': write failed (disk full?)");
      }
  });
  std::size_t buffered = 0;
  std::vector<char> row_out(tile_row_bytes);
  const RowCopy copy(in.fields(), withoutFields(fields, {"tile_row", "tile_core"}));
  std::uint64_t kept = before.back();  // the row among the finite points: the row of segments.ply
  share.run([&] {
    forEachRow(
        in, input, nan, share.begin, share.end,
        [&](std::uint64_t, const char* row, double x, double y, double) {
          copy.apply(row, row_out.data());
          const double row_index = static_cast<double>(kept++);
          std::memcpy(row_out.data() + kept_bytes, &row_index, 8);
          const TileKey own = ownerOf(x, y);
          int holders = 0;
          place(x, y, [&](TileKey t) { holders += writers.count(t) ? 1 : 0; });
          place(x, y, [&](TileKey t) {
            const auto w = writers.find(t);
            if (w == writers.end())
              return;
            // 0: held for a neighbour; 1: owned; 2: owned and held by a neighbour too.
            row_out[kept_bytes + 8] = static_cast<char>(t != own ? 0 : holders > 1 ? 2 : 1);
            w->second.pending.insert(w->second.pending.end(), row_out.begin(), row_out.end());
            buffered += row_out.size();
          });
          if (buffered > kBufferedBytes) {
            for (auto& [key, w] : writers)
              w.flush();
            buffered = 0;
          }
        },
        progress, passes_done * mine, passes_planned * mine);
    for (auto& [key, w] : writers)
      w.flush();
  });
  // Every tile holds exactly the rows its header announces (each checked by the rank that
  // created it; opened, so that a network filesystem reports the size the other ranks wrote).
  for (TileInfo& t : m.tiles)
    t.bytes = plyHeader(fields, t.points).size() + t.points * tile_row_bytes;
  share.run([&] {
    const int rank = work ? work->rank() : 0, ranks = work ? work->ranks() : 1;
    for (std::size_t k = static_cast<std::size_t>(rank); k < m.tiles.size();
         k += static_cast<std::size_t>(ranks)) {
      const std::string path = dir + "/" + m.tiles[k].name() + ".ply";
      std::ifstream tile(path, std::ios::binary | std::ios::ate);
      if (!tile || static_cast<std::uint64_t>(tile.tellg()) != m.tiles[k].bytes)
        throw RunError("tile '" + path + "': write failed (disk full?)");
    }
  });
  return m;
}

TileTree TilingManifest::tree() const {
  std::vector<TileKey> leaves;
  for (const TileInfo& t : tiles)
    leaves.push_back(t.key);
  return TileTree::fromLeaves(TileGrid(size, buffer), leaves);
}

std::string verifyTiles(const TilingManifest& m, const std::string& dir) {
  for (const TileInfo& t : m.tiles) {
    std::error_code ec;
    const std::uint64_t bytes = std::filesystem::file_size(dir + "/" + t.name() + ".ply", ec);
    if (ec)
      return t.name() + ".ply is missing";
    if (bytes != t.bytes)
      return t.name() + ".ply holds " + std::to_string(bytes) + " bytes, written " +
             std::to_string(t.bytes);
  }
  return "";
}

std::string manifestText(const TilingManifest& m) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  out << YAML::Key << "slipfit_tiling" << YAML::Value << 5;
  out << YAML::Key << "input" << YAML::Value << m.input;
  out << YAML::Key << "input_bytes" << YAML::Value << m.input_bytes;
  out << YAML::Key << "input_mtime" << YAML::Value << m.input_mtime;
  out << YAML::Key << "size" << YAML::Value << m.size;
  out << YAML::Key << "buffer" << YAML::Value << m.buffer;
  out << YAML::Key << "max_points" << YAML::Value << m.max_points;
  out << YAML::Key << "points" << YAML::Value << m.points;
  out << YAML::Key << "dropped" << YAML::Value << m.dropped;
  out << YAML::Key << "double_coordinates" << YAML::Value << m.double_coordinates;
  out << YAML::Key << "lo" << YAML::Value << YAML::Flow << YAML::BeginSeq << m.lo[0] << m.lo[1]
      << m.lo[2] << YAML::EndSeq;
  out << YAML::Key << "hi" << YAML::Value << YAML::Flow << YAML::BeginSeq << m.hi[0] << m.hi[1]
      << m.hi[2] << YAML::EndSeq;
  if (m.sensor) {
    out << YAML::Key << "sensor" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (const double v : *m.sensor)
      out << v;
    out << YAML::EndSeq;
  }
  out << YAML::Key << "tiles" << YAML::Value << YAML::BeginSeq;
  for (const TileInfo& t : m.tiles)
    out << YAML::Flow << YAML::BeginSeq << t.key.i << t.key.j << t.key.level << t.points << t.core
        << t.bytes << YAML::EndSeq;
  out << YAML::EndSeq << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

bool readManifest(const std::string& path, TilingManifest& m) {
  if (!std::filesystem::is_regular_file(path))
    return false;
  try {
    const YAML::Node n = YAML::LoadFile(path);
    if (!n.IsMap() || !n["slipfit_tiling"] || n["slipfit_tiling"].as<int>() != 5)
      return false;
    m.input = n["input"].as<std::string>();
    m.input_bytes = n["input_bytes"].as<std::uint64_t>();
    m.input_mtime = n["input_mtime"].as<std::int64_t>();
    m.size = n["size"].as<double>();
    m.buffer = n["buffer"].as<double>();
    m.max_points = n["max_points"].as<std::uint64_t>();
    m.points = n["points"].as<std::uint64_t>();
    m.dropped = n["dropped"].as<std::uint64_t>();
    m.double_coordinates = n["double_coordinates"].as<bool>();
    for (int a = 0; a < 3; ++a) {
      m.lo[a] = n["lo"][a].as<double>();
      m.hi[a] = n["hi"][a].as<double>();
    }
    m.sensor.reset();
    if (n["sensor"]) {
      std::array<double, 7> pose{};
      for (std::size_t k = 0; k < pose.size(); ++k)
        pose[k] = n["sensor"][k].as<double>();
      m.sensor = pose;
    }
    m.tiles.clear();
    for (const auto& t : n["tiles"]) {
      TileInfo info;
      info.key = {t[0].as<std::int64_t>(), t[1].as<std::int64_t>(), t[2].as<int>()};
      info.points = t[3].as<std::uint64_t>();
      info.core = t[4].as<std::uint64_t>();
      info.bytes = t[5].as<std::uint64_t>();
      m.tiles.push_back(info);
    }
    m.tree();  // the tiles come from splits of the grid
    return true;
  } catch (const YAML::Exception&) {
    return false;
  } catch (const std::invalid_argument&) {
    return false;
  }
}

}  // namespace slipfit::pipeline::tiling
