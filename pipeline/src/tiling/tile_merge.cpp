#include "tile_merge.h"

#include "../png_file.h"
#include "fit_bytes.h"
#include "packed_values.h"
#include "ply_rows.h"
#include "segments_las.h"
#include "tile_job.h"
#include "worker_pool.h"

#include "slipfit/fitting/primitives.h"
#include "slipfit/fitting/weighted_fit.h"
#include "slipfit/pipeline/cloud_io.h"
#include "slipfit/pipeline/errors.h"
#include "slipfit/pipeline/primitives_report.h"
#include "slipfit/render/legend.h"
#include "slipfit/render/segment_palette.h"
#include "slipfit/tiling/segment_joining.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <numeric>
#include <optional>

namespace slipfit::pipeline::tiling {

namespace {

constexpr Eigen::Index kMostRefitPoints = 200000;

/// A segment of the whole cloud while it is merged.
struct Joined {
  std::uint64_t core_points = 0;
  int type = -1;
  double inlier_distance = 0.0;
  std::string seed_slippage_type;
  std::size_t pieces_left = 0;  ///< pieces whose samples are still to come
  std::vector<double> samples;  ///< x, y, z, nx, ny, nz, weight per sample
  /// The fit of its largest piece that has one (relative to the merge's origin): where the closed
  /// form on the samples fails, the refit starts from it.
  std::optional<Primitive> start;
  std::uint64_t start_points = 0;
  FitResult fit;
  double sum_squares = 0.0, max_distance = 0.0;
  std::uint64_t inliers = 0;
};

}  // namespace

FitResult refitJoined(PrimitiveType type, const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                      const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                      const Eigen::Ref<const Eigen::VectorXd>& weights,
                      const std::optional<Primitive>& start) {
  FitResult fit = fitPrimitive(type, points, normals, weights);
  if (!fit.ok() && start && start->index() == static_cast<std::size_t>(type)) {
    FitResult warm = fitFrom(*start, points, weights);
    if (warm.ok())
      return warm;
  }
  return fit;
}

namespace {

/// Refits \a j on its samples (at most kMostRefitPoints: every k-th, its weight × k), the
/// coordinates taken relative to \a origin.
void refit(Joined& j, const Eigen::Vector3d& origin) {
  const auto all = static_cast<Eigen::Index>(j.samples.size() / 7);
  if (all == 0)  // every piece that owns points has a sample in a tile that verifies
    throw RunError("a joined segment of " + std::to_string(j.core_points) +
                   " points has no samples in its tiles' samples.bin");
  const Eigen::Index stride = (all + kMostRefitPoints - 1) / kMostRefitPoints;
  const Eigen::Index n = (all + stride - 1) / stride;
  Eigen::Matrix3Xd points(3, n), normals(3, n);
  Eigen::VectorXd weights(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double* s = j.samples.data() + 7 * k * stride;
    points.col(k) = Eigen::Vector3d(s[0], s[1], s[2]) - origin;
    normals.col(k) = Eigen::Vector3d(s[3], s[4], s[5]);
    weights(k) = s[6] * static_cast<double>(stride);
  }
  j.fit = refitJoined(static_cast<PrimitiveType>(j.type), points, normals, weights, j.start);
  j.samples.clear();
  j.samples.shrink_to_fit();
}

/// The distances of one tile's points to their joined segment's fit.
struct Distances {
  double sum_squares = 0.0, max_distance = 0.0;
  std::uint64_t inliers = 0;
};

/// What writing one tile's rows of segments.ply gave.
struct TileRows {
  std::uint64_t points = 0, assigned = 0;
  std::map<std::int32_t, Distances> distances;  ///< per segment of the whole cloud
  std::vector<float> picture_points, picture_normals;
  std::vector<std::uint8_t> picture_colours;
};

/// Rows of the points a tile owns, ascending, read from a tile file or a tile run's output (their
/// tile_row where tile_core is not 0).
class OwnedRows {
 public:
  explicit OwnedRows(const std::string& ply) : in_(ply) {
    const StreamField* row = findField(in_.fields(), "tile_row");
    const StreamField* core = findField(in_.fields(), "tile_core");
    if (!row || !core)
      throw RunError("'" + ply + "': no tile_row and tile_core");
    row_ = fieldAt(*row);
    core_ = fieldAt(*core);
  }
  /// The next owned row; false after the last.
  bool next(std::uint64_t& row) {
    for (;;) {
      if (k_ == n_) {
        if (first_ >= in_.size())
          return false;
        n_ = std::min<std::uint64_t>(1u << 16, in_.size() - first_);
        in_.readRecords(first_, n_, rows_);
        first_ += n_;
        k_ = 0;
      }
      const char* r = rows_.data() + k_++ * in_.recordBytes();
      if (core_.get(r) != 0.0) {
        row = static_cast<std::uint64_t>(row_.get(r));
        return true;
      }
    }
  }

 private:
  CloudStream in_;
  FieldAt row_, core_;
  std::vector<char> rows_;
  std::uint64_t first_ = 0, n_ = 0, k_ = 0;
};

/// The rows of the points the tile file \a tile_ply owns that its run's \a output_ply does not
/// hold (a stage of the run removed them: a crop), ascending.
std::vector<std::uint64_t> removedRows(const std::string& tile_ply, const std::string& output_ply) {
  OwnedRows in(tile_ply), out(output_ply);
  std::vector<std::uint64_t> removed;
  std::uint64_t a = 0, b = 0;
  bool more = out.next(b);
  while (in.next(a)) {
    if (more && a == b) {
      more = out.next(b);
      continue;
    }
    if (more && b < a)
      throw RunError("'" + output_ply + "': row " + std::to_string(b) + " is not its tile's, or " +
                     "out of order");
    removed.push_back(a);
  }
  if (more)
    throw RunError("'" + output_ply + "': row " + std::to_string(b) + " is not its tile's");
  return removed;
}

/// Writes the points a tile owns from its \a ply as rows of \a fields in \a file, whose rows
/// start at byte \a offset, with the labels of the whole cloud (\a global: per tile label), their
/// colours and types. A point's row in the file is its tile_row less the rows before it that no
/// tile wrote (\a missing, ascending): the input's order. Every \a every-th row of the file is
/// kept for the picture when \a picture.
TileRows writeTileRows(const std::string& ply, const std::vector<StreamField>& fields,
                       const PositionalFile& file, std::uint64_t offset, std::uint64_t total,
                       const std::vector<std::uint64_t>& missing, std::uint64_t every, bool picture,
                       const Eigen::Vector3d& origin, const std::vector<std::int32_t>& global,
                       const std::vector<Joined>& joined) {
  CloudStream in(ply);
  const std::vector<StreamField> kept = withoutFields(in.fields(), {"tile_row", "tile_core"});
  if (kept.size() != fields.size() ||
      kept.back().offset + kept.back().bytes != fields.back().offset + fields.back().bytes)
    throw RunError("'" + ply + "': its fields differ from the first tile's");
  const StreamField* core_f = findField(in.fields(), "tile_core");
  const StreamField* label_f = findField(fields, "label");
  const StreamField* type_f = findField(fields, "primitive");
  const StreamField* rgb_f[3] = {findField(fields, "red"), findField(fields, "green"),
                                 findField(fields, "blue")};
  if (!core_f || !label_f || !type_f || !rgb_f[0] || !rgb_f[1] || !rgb_f[2])
    throw RunError("'" + ply + "': not a segmentation output of a tile");
  const FieldAt core = fieldAt(*core_f), label = fieldAt(*label_f), type = fieldAt(*type_f);
  const StreamField* row_f = findField(in.fields(), "tile_row");
  if (!row_f)
    throw RunError("'" + ply + "': not a segmentation output of a tile");
  const FieldAt tile_row = fieldAt(*row_f);
  const FieldAt colour[3] = {fieldAt(*rgb_f[0]), fieldAt(*rgb_f[1]), fieldAt(*rgb_f[2])};
  const FieldAt xyz[3] = {fieldAt(*findField(fields, "x")), fieldAt(*findField(fields, "y")),
                          fieldAt(*findField(fields, "z"))};
  const RowCopy copy(in.fields(), fields);
  const StreamField* n_f[3] = {findField(fields, "normal_x"), findField(fields, "normal_y"),
                               findField(fields, "normal_z")};
  if (!n_f[0])  // as written to the file
    for (int a = 0; a < 3; ++a)
      n_f[a] = findField(fields, std::string("n") + "xyz"[a]);
  const std::uint64_t bytes = fields.back().offset + fields.back().bytes;

  TileRows w;
  std::int32_t last = -1;  // runs of one label are common: its sums are looked up once a run
  Distances* sums = nullptr;
  std::vector<char> rows, row_out;
  constexpr std::uint64_t kChunk = 1u << 16;
  // Runs of consecutive rows of the file are written at once.
  std::uint64_t run_first = 0, previous = 0;
  std::size_t skipped = 0;  // missing rows before the current point
  const auto flush = [&] {
    if (!row_out.empty())
      file.write(offset + run_first * bytes, row_out.data(), row_out.size());
    row_out.clear();
  };
  for (std::uint64_t r0 = 0; r0 < in.size(); r0 += kChunk) {
    const std::uint64_t n = std::min(kChunk, in.size() - r0);
    in.readRecords(r0, n, rows);
    for (std::uint64_t r = 0; r < n; ++r) {
      const char* row = rows.data() + r * in.recordBytes();
      if (core.get(row) == 0.0)
        continue;
      const auto input_row = static_cast<std::uint64_t>(tile_row.get(row));
      while (skipped < missing.size() && missing[skipped] < input_row)
        ++skipped;
      const std::uint64_t place = input_row - skipped;
      if (place >= total || (w.points > 0 && place <= previous))
        throw RunError("'" + ply + "': tile_row " + std::to_string(input_row) +
                       " out of order or past the " + std::to_string(total) + " points written");
      if (row_out.empty() || place != previous + 1) {
        flush();
        run_first = place;
      }
      previous = place;
      const std::size_t at = row_out.size();
      row_out.resize(at + bytes);
      char* o = row_out.data() + at;
      copy.apply(row, o);
      const auto l = static_cast<std::int64_t>(label.get(o));
      const std::int32_t g =
          l < 0 || static_cast<std::uint64_t>(l) >= global.size() ? -1 : global[l];
      label.set(o, g);
      const Rgb c = g < 0 ? kUnassignedColour : segmentColour(static_cast<std::size_t>(g));
      for (int a = 0; a < 3; ++a)
        colour[a].set(o, c[static_cast<std::size_t>(a)]);
      if (picture && place % every == 0) {
        for (int a = 0; a < 3; ++a) {
          w.picture_points.push_back(static_cast<float>(xyz[a].get(o) - origin[a]));
          w.picture_normals.push_back(n_f[a] ? static_cast<float>(fieldAt(*n_f[a]).get(o)) : 0.0f);
          w.picture_colours.push_back(c[static_cast<std::size_t>(a)]);
        }
      }
      ++w.points;
      if (g < 0) {
        type.set(o, -1);
        continue;
      }
      const Joined& j = joined[static_cast<std::size_t>(g)];
      type.set(o, static_cast<double>(j.fit.type));
      const Eigen::Vector3d p(xyz[0].get(o), xyz[1].get(o), xyz[2].get(o));
      const double d = j.fit.ok() ? distance(p - origin, j.fit.refined) : 0.0;
      if (g != last) {
        sums = &w.distances[g];  // std::map: the pointer stays valid as entries are added
        last = g;
      }
      sums->sum_squares += d * d;
      sums->max_distance = std::max(sums->max_distance, d);
      sums->inliers += d <= j.inlier_distance ? 1 : 0;
      ++w.assigned;
    }
    flush();
  }
  return w;
}

/// Each label's fit in a tile's report (\a path), relative to \a origin; labels whose fit failed
/// or is not a primitive are left out.
std::map<std::int32_t, Primitive> readTileFits(const std::string& path,
                                               const Eigen::Vector3d& origin) {
  std::map<std::int32_t, Primitive> fits;
  try {
    for (const YAML::Node& entry : YAML::LoadFile(path)["primitives"])
      if (entry["label"])
        if (const std::optional<Primitive> p = readPrimitive(entry, origin))
          fits.emplace(entry["label"].as<std::int32_t>(), *p);
  } catch (const YAML::Exception& e) {
    throw RunError("'" + path + "': " + e.what());
  }
  return fits;
}

}  // namespace

std::vector<std::size_t> mergeShares(const TilingManifest& m, int ranks) {
  std::uint64_t all = 0;
  for (const TileInfo& t : m.tiles)
    all += t.core;
  std::vector<std::size_t> first(static_cast<std::size_t>(ranks) + 1, m.tiles.size());
  first[0] = 0;
  std::uint64_t before = 0;  // core points of the tiles before t
  std::size_t r = 1;
  for (std::size_t t = 0; t < m.tiles.size(); ++t) {
    // Tile t goes to the rank whose share of the points its first point falls in.
    while (r <= static_cast<std::size_t>(ranks) - 1 &&
           before >=
               all / static_cast<std::uint64_t>(ranks) * r +
                   all % static_cast<std::uint64_t>(ranks) * r / static_cast<std::uint64_t>(ranks))
      first[r++] = t;
    before += m.tiles[t].core;
  }
  while (r <= static_cast<std::size_t>(ranks) - 1)
    first[r++] = m.tiles.size();
  return first;
}

MergeSummary mergeTiles(const TilingManifest& m, const std::string& tiles_dir,
                        const std::string& runs_dir, const JoinedAcrossTiles::Files& files,
                        const RenderRequest* render, int workers, OutputFiles* outputs,
                        WorkDistribution& work, MergeTimes* times) {
  const std::string& segments_name = files.segments;
  const std::string& report_name = files.report;
  const std::size_t tiles = m.tiles.size();
  const auto dirOf = [&](std::size_t t) { return runs_dir + "/" + m.tiles[t].name(); };
  const auto clock = [] { return std::chrono::steady_clock::now(); };
  const auto since = [](auto start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  MergeTimes spent;
  // This rank's tiles: a run of them holding its share of the points.
  const std::vector<std::size_t> shares = mergeShares(m, work.ranks());
  const std::size_t mine_first = shares[static_cast<std::size_t>(work.rank())];
  const std::size_t mine_end = shares[static_cast<std::size_t>(work.rank()) + 1];
  const std::size_t mine = mine_end - mine_first;
  // The tiles by the grid tile they lie in: a tile's buffer reaches only into the grid tiles
  // around its own (buffer < size / 2).
  const TileTree tree = m.tree();
  std::map<TileKey, std::vector<std::size_t>> by_grid_tile;
  for (std::size_t t = 0; t < tiles; ++t)
    by_grid_tile[TileTree::ancestor(m.tiles[t].key, 0)].push_back(t);
  // The tiles after t (in the manifest's order) that may share points with it.
  const auto neighboursAfter = [&](std::size_t t) {
    std::vector<std::size_t> after;
    const TileKey own = TileTree::ancestor(m.tiles[t].key, 0);
    for (std::int64_t di = -1; di <= 1; ++di)
      for (std::int64_t dj = -1; dj <= 1; ++dj) {
        const auto near = by_grid_tile.find({own.i + di, own.j + dj});
        if (near == by_grid_tile.end())
          continue;
        for (const std::size_t u : near->second)
          if (u > t && tree.overlap(m.tiles[t].key, m.tiles[u].key))
            after.push_back(u);
      }
    std::sort(after.begin(), after.end());
    return after;
  };

  // 1. Each rank reads its tiles: their segments (the pieces), the points they own, the rows a
  // run removed (a crop), and the joins of each with its neighbours after it; what every rank
  // found is shared with all.
  auto start = clock();
  std::vector<std::vector<TileSegment>> pieces(tiles);
  std::vector<std::uint64_t> owned(tiles);
  std::vector<std::vector<std::uint64_t>> removed(tiles);
  std::vector<std::vector<std::array<std::int64_t, 3>>> joins(tiles);  // (label, tile, label)
  work.together([&] {
    forEachOnWorkers(mine, workers, [&](std::size_t k) {
      const std::size_t t = mine_first + k;
      pieces[t] = readTileSegments(dirOf(t));
      const TileLabels here = readTileLabels(dirOf(t));
      owned[t] = here.owned;
      if (owned[t] > m.tiles[t].core)
        throw RunError("'" + dirOf(t) + "/" + segments_name + "': " + std::to_string(owned[t]) +
                       " points owned, the tile owns " + std::to_string(m.tiles[t].core));
      if (owned[t] < m.tiles[t].core)
        removed[t] = removedRows(tiles_dir + "/" + m.tiles[t].name() + ".ply",
                                 dirOf(t) + "/" + segments_name);
      std::vector<int> types_here;
      for (const TileSegment& s : pieces[t])
        types_here.push_back(s.type);
      for (const std::size_t u : neighboursAfter(t)) {
        const TileLabels there = readTileLabels(dirOf(u));
        std::vector<int> types_there;
        for (const TileSegment& s : readTileSegments(dirOf(u)))
          types_there.push_back(s.type);
        OverlapCounts counts;
        try {
          counts = countOverlap(here.rows, here.labels, there.rows, there.labels);
        } catch (const std::invalid_argument& e) {
          throw RunError("tiles '" + dirOf(t) + "' and '" + dirOf(u) + "': " + e.what());
        }
        for (const auto& [a, b] : segmentsToJoin(counts, types_here, types_there))
          joins[t].push_back({a, static_cast<std::int64_t>(u), b});
      }
    });
  });
  {
    std::string bytes;
    for (std::size_t t = mine_first; t < mine_end; ++t) {
      pack(bytes, owned[t]);
      pack(bytes, static_cast<std::uint64_t>(pieces[t].size()));
      for (const TileSegment& s : pieces[t]) {
        pack(bytes, s.type);
        pack(bytes, s.core_points);
        pack(bytes, s.inlier_distance);
        packText(bytes, s.seed_slippage_type);
      }
      pack(bytes, static_cast<std::uint64_t>(removed[t].size()));
      for (const std::uint64_t row : removed[t])
        pack(bytes, row);
      pack(bytes, static_cast<std::uint64_t>(joins[t].size()));
      for (const auto& j : joins[t])
        for (const std::int64_t v : j)
          pack(bytes, v);
    }
    const std::vector<std::string> all =
        work.ranks() == 1 ? std::vector<std::string>{} : work.allGather(bytes);
    for (std::size_t r = 0; r < all.size(); ++r) {
      if (static_cast<int>(r) == work.rank())
        continue;
      Unpack in(all[r]);
      for (std::size_t t = shares[r]; t < shares[r + 1]; ++t) {
        owned[t] = in.next<std::uint64_t>();
        pieces[t].resize(static_cast<std::size_t>(in.next<std::uint64_t>()));
        for (TileSegment& s : pieces[t]) {
          s.type = in.next<int>();
          s.core_points = in.next<std::uint64_t>();
          s.inlier_distance = in.next<double>();
          s.seed_slippage_type = in.text();
        }
        removed[t].resize(static_cast<std::size_t>(in.next<std::uint64_t>()));
        for (std::uint64_t& row : removed[t])
          row = in.next<std::uint64_t>();
        joins[t].resize(static_cast<std::size_t>(in.next<std::uint64_t>()));
        for (auto& j : joins[t])
          for (std::int64_t& v : j)
            v = in.next<std::int64_t>();
      }
    }
  }
  spent.joins = since(start);

  // 2. The segments of the whole cloud, on every rank alike (the pieces and joins are small):
  // the sets that own points, largest first (as an untiled run numbers them), ties by their
  // first piece.
  start = clock();
  std::vector<std::size_t> first(tiles + 1, 0);
  for (std::size_t t = 0; t < tiles; ++t)
    first[t + 1] = first[t] + pieces[t].size();
  DisjointSets sets(first[tiles]);
  MergeSummary summary;
  // The joins are applied in tile order (the sets' representatives do not depend on it).
  for (std::size_t t = 0; t < tiles; ++t)
    for (const auto& [a, u, b] : joins[t]) {
      sets.join(first[t] + static_cast<std::size_t>(a),
                first[static_cast<std::size_t>(u)] + static_cast<std::size_t>(b));
      ++summary.joins;
    }
  joins.clear();
  std::map<std::size_t, Joined> by_root;
  std::map<std::size_t, std::size_t> first_tile_of_root;  // the lowest tile of a piece
  for (std::size_t t = 0; t < tiles; ++t)
    for (std::size_t l = 0; l < pieces[t].size(); ++l) {
      const TileSegment& s = pieces[t][l];
      if (s.core_points == 0)
        continue;
      const std::size_t root = sets.find(first[t] + l);
      Joined& j = by_root[root];
      first_tile_of_root.emplace(root, t);
      // The type of the largest piece; the widest tolerance of any piece.
      if (j.type < 0 || s.core_points > j.core_points) {
        j.type = s.type;
        j.seed_slippage_type = s.seed_slippage_type;
      }
      j.core_points += s.core_points;
      j.inlier_distance = std::max(j.inlier_distance, s.inlier_distance);
      ++j.pieces_left;
      ++summary.pieces;
    }
  std::vector<std::size_t> roots;
  for (const auto& [root, j] : by_root)
    roots.push_back(root);
  std::stable_sort(roots.begin(), roots.end(), [&](std::size_t a, std::size_t b) {
    return by_root[a].core_points > by_root[b].core_points;
  });
  std::vector<Joined> joined(roots.size());
  std::vector<int> refitter(roots.size());  // the rank that refits each segment
  std::map<std::size_t, std::int32_t> id_of_root;
  for (std::size_t k = 0; k < roots.size(); ++k) {
    joined[k] = std::move(by_root[roots[k]]);
    id_of_root[roots[k]] = static_cast<std::int32_t>(k);
    const std::size_t t = first_tile_of_root.at(roots[k]);
    refitter[k] =
        static_cast<int>(std::upper_bound(shares.begin(), shares.end(), t) - shares.begin()) - 1;
  }
  by_root.clear();
  // Each tile's labels → the whole cloud's (−1: a piece that owns no point).
  std::vector<std::vector<std::int32_t>> global(tiles);
  for (std::size_t t = 0; t < tiles; ++t)
    for (std::size_t l = 0; l < pieces[t].size(); ++l)
      global[t].push_back(pieces[t][l].core_points == 0 ? -1
                                                        : id_of_root.at(sets.find(first[t] + l)));
  const auto idOf = [&](std::size_t t, std::int32_t label) -> std::int32_t {
    return label < 0 || static_cast<std::size_t>(label) >= global[t].size()
               ? -1
               : global[t][static_cast<std::size_t>(label)];
  };
  const auto refitHere = [&](std::int32_t g) {
    return g >= 0 && refitter[static_cast<std::size_t>(g)] == work.rank();
  };
  spent.segments = since(start);

  // 3. Refits on the union of the pieces' samples: each segment by the rank of its first tile,
  // as soon as its last piece is read (the tiles in order, as one process reads them); the fits
  // are shared with every rank. The refit starts from the fit of the segment's largest piece
  // where its closed form fails.
  start = clock();
  const Eigen::Vector3d origin = globalShift(Eigen::Vector3d(m.lo[0], m.lo[1], m.lo[2]),
                                             Eigen::Vector3d(m.hi[0], m.hi[1], m.hi[2]));
  work.together([&] {
    for (std::size_t t = 0; t < tiles; ++t) {
      bool needed = false;
      for (std::size_t l = 0; l < pieces[t].size(); ++l)
        needed = needed || refitHere(idOf(t, static_cast<std::int32_t>(l)));
      if (!needed)
        continue;
      const std::map<std::int32_t, Primitive> fits =
          readTileFits(dirOf(t) + "/" + report_name, origin);
      for (std::size_t l = 0; l < pieces[t].size(); ++l) {
        const std::int32_t g = idOf(t, static_cast<std::int32_t>(l));
        if (!refitHere(g))
          continue;
        Joined& j = joined[static_cast<std::size_t>(g)];
        const auto own = fits.find(static_cast<std::int32_t>(l));
        if (own != fits.end() && pieces[t][l].core_points > j.start_points) {
          j.start = own->second;
          j.start_points = pieces[t][l].core_points;
        }
      }
      const TileSamples s = readTileSamples(dirOf(t));
      for (std::size_t k = 0; k < s.labels.size(); ++k) {
        const std::int32_t g = idOf(t, s.labels[k]);
        if (!refitHere(g))
          continue;
        auto& v = joined[static_cast<std::size_t>(g)].samples;
        const auto c = static_cast<Eigen::Index>(k);
        v.insert(v.end(), {s.points(0, c), s.points(1, c), s.points(2, c), s.normals(0, c),
                           s.normals(1, c), s.normals(2, c), s.weights[k]});
      }
      std::vector<std::size_t> complete;
      for (std::size_t l = 0; l < pieces[t].size(); ++l) {
        const std::int32_t g = idOf(t, static_cast<std::int32_t>(l));
        if (refitHere(g) && --joined[static_cast<std::size_t>(g)].pieces_left == 0)
          complete.push_back(static_cast<std::size_t>(g));
      }
      forEachOnWorkers(complete.size(), workers,
                       [&](std::size_t k) { refit(joined[complete[k]], origin); });
    }
  });
  if (work.ranks() > 1) {
    std::string bytes;
    for (std::size_t g = 0; g < joined.size(); ++g)
      if (refitter[g] == work.rank())
        packFit(bytes, joined[g].fit);
    const std::vector<std::string> all = work.allGather(bytes);
    std::vector<Unpack> in;
    for (const std::string& b : all)
      in.emplace_back(b);
    for (std::size_t g = 0; g < joined.size(); ++g)
      joined[g].fit = unpackFit(in[static_cast<std::size_t>(refitter[g])]);
  }
  spent.refits = since(start);

  // 4. segments.ply: each tile's own points, with the whole cloud's labels and colours, in the
  // input's order, each rank its tiles. The rows have one size and each point's place in the
  // file is its tile_row (its row among the input's finite points) less the rows before it that
  // a tile's run removed (a crop): tiles are written side by side, each point at its place
  // (pwrite), and each tile's sums are kept apart and added in tile order by the leader.
  start = clock();
  std::uint64_t total = 0;
  std::vector<std::uint64_t> missing;
  for (std::size_t t = 0; t < tiles; ++t) {
    total += owned[t];
    missing.insert(missing.end(), removed[t].begin(), removed[t].end());
  }
  removed.clear();
  std::sort(missing.begin(), missing.end());
  // The picture's points: every k-th point written, relative to the origin (float keeps them).
  const std::uint64_t every =
      std::max<std::uint64_t>(1, (total + kRenderedPoints - 1) / kRenderedPoints);
  std::vector<StreamField> fields;
  std::string merged;  // the temporary path of segments.ply until the outputs are committed
  work.together([&] {
    fields = withoutFields(CloudStream(dirOf(0) + "/" + segments_name).fields(),
                           {"tile_row", "tile_core"});
    if (!outputs)
      return;
    outputs->add(segments_name, [&](const std::string& path) {
      merged = path;
      const std::string header = plyHeader(fields, total);
      std::ofstream out(path, std::ios::binary | std::ios::trunc);
      writeOrFail(out, header.data(), header.size(), path);
      out.close();
      if (!out)
        throw RunError("'" + path + "': write failed (disk full?)");
    });
  });
  merged = work.broadcast(merged);
  const std::uint64_t header_bytes = plyHeader(fields, total).size();
  std::vector<TileRows> written(tiles);
  work.together([&] {
    PositionalFile file(merged);
    forEachOnWorkers(mine, workers, [&](std::size_t k) {
      const std::size_t t = mine_first + k;
      written[t] = writeTileRows(dirOf(t) + "/" + segments_name, fields, file, header_bytes, total,
                                 missing, every, render != nullptr, origin, global[t], joined);
      if (written[t].points != owned[t])
        throw RunError("'" + dirOf(t) + "/" + segments_name +
                       "': " + std::to_string(written[t].points) +
                       " points owned, labels.bin says " + std::to_string(owned[t]));
    });
    file.close();
  });
  if (work.ranks() > 1) {
    std::string bytes;
    for (std::size_t t = mine_first; t < mine_end; ++t) {
      const TileRows& w = written[t];
      pack(bytes, w.points);
      pack(bytes, w.assigned);
      pack(bytes, static_cast<std::uint64_t>(w.distances.size()));
      for (const auto& [g, d] : w.distances) {
        pack(bytes, g);
        pack(bytes, d.sum_squares);
        pack(bytes, d.max_distance);
        pack(bytes, d.inliers);
      }
      pack(bytes, static_cast<std::uint64_t>(w.picture_colours.size()));
      bytes.append(reinterpret_cast<const char*>(w.picture_points.data()),
                   w.picture_points.size() * sizeof(float));
      bytes.append(reinterpret_cast<const char*>(w.picture_normals.data()),
                   w.picture_normals.size() * sizeof(float));
      bytes.append(reinterpret_cast<const char*>(w.picture_colours.data()),
                   w.picture_colours.size());
    }
    const std::vector<std::string> all = work.gather(bytes);
    for (std::size_t r = 0; r < all.size(); ++r) {
      if (static_cast<int>(r) == work.rank())
        continue;
      Unpack in(all[r]);
      for (std::size_t t = shares[r]; t < shares[r + 1]; ++t) {
        TileRows& w = written[t];
        w.points = in.next<std::uint64_t>();
        w.assigned = in.next<std::uint64_t>();
        for (auto n = in.next<std::uint64_t>(); n > 0; --n) {
          Distances& d = w.distances[in.next<std::int32_t>()];
          d.sum_squares = in.next<double>();
          d.max_distance = in.next<double>();
          d.inliers = in.next<std::uint64_t>();
        }
        const auto values = static_cast<std::size_t>(in.next<std::uint64_t>());
        w.picture_points.resize(values);
        w.picture_normals.resize(values);
        w.picture_colours.resize(values);
        for (float& v : w.picture_points)
          v = in.next<float>();
        for (float& v : w.picture_normals)
          v = in.next<float>();
        for (std::uint8_t& v : w.picture_colours)
          v = in.next<std::uint8_t>();
      }
    }
  }
  spent.rows = since(start);
  summary.segments = joined.size();
  if (!outputs) {  // the leader reports and writes the rest
    if (times)
      *times = spent;
    return summary;
  }

  // 5. The leader: the sums in tile order, the LAS file, the picture and primitives.yaml.
  start = clock();
  if (!files.las.empty())
    outputs->add(files.las,
                 [&](const std::string& path) { writeSegmentsLas(merged, m.input, path); });
  std::vector<float> picture_points, picture_normals;
  std::vector<std::uint8_t> picture_colours;
  for (const TileRows& w : written) {
    summary.points += w.points;
    summary.assigned += w.assigned;
    for (const auto& [g, d] : w.distances) {
      Joined& j = joined[static_cast<std::size_t>(g)];
      j.sum_squares += d.sum_squares;
      j.max_distance = std::max(j.max_distance, d.max_distance);
      j.inliers += d.inliers;
    }
    picture_points.insert(picture_points.end(), w.picture_points.begin(), w.picture_points.end());
    picture_normals.insert(picture_normals.end(), w.picture_normals.begin(),
                           w.picture_normals.end());
    picture_colours.insert(picture_colours.end(), w.picture_colours.begin(),
                           w.picture_colours.end());
  }
  written.clear();

  if (render) {
    const auto n = static_cast<Eigen::Index>(picture_points.size() / 3);
    const Eigen::Map<const Eigen::Matrix3Xf> x(picture_points.data(), 3, n);
    const Eigen::Map<const Eigen::Matrix3Xf> normals(picture_normals.data(), 3, n);
    const Eigen::Map<const Eigen::Matrix<std::uint8_t, 3, Eigen::Dynamic>> rgb(
        picture_colours.data(), 3, n);
    RenderParameters camera = render->camera;
    if (camera.eye)
      *camera.eye -= origin;  // the config's eye is in the input's frame
    std::vector<std::uint8_t> image = renderSplats(x, rgb, normals, camera);
    if (camera.legend) {
      std::vector<PrimitiveType> types;
      std::vector<std::size_t> points;
      for (const Joined& j : joined) {
        types.push_back(j.fit.type);
        points.push_back(static_cast<std::size_t>(j.core_points));
      }
      drawLegend(
          image, camera.width, camera.height,
          segmentLegend(types, points, static_cast<std::size_t>(summary.points - summary.assigned)),
          legendScale(camera.height), kLegendRows);
    }
    outputs->add(render->name, [&](const std::string& path) {
      detail::writeRgbPng(path, image, camera.width, camera.height);
    });
  }

  std::vector<PrimitiveRecord> records;
  for (std::size_t k = 0; k < joined.size(); ++k) {
    const Joined& j = joined[k];
    PrimitiveRecord r;
    r.id = static_cast<int>(k);
    r.label = static_cast<int>(k);
    r.fit = j.fit;
    if (j.core_points > 0)
      r.fit.rms_distance = std::sqrt(j.sum_squares / static_cast<double>(j.core_points));
    r.fit.max_distance = j.max_distance;
    r.inlier_distance = j.inlier_distance;
    r.inliers = j.inliers;
    r.extra["points"] = std::to_string(j.core_points);
    if (!j.seed_slippage_type.empty())
      r.extra["seed_slippage_type"] = j.seed_slippage_type;
    records.push_back(std::move(r));
  }
  outputs->addText(report_name, primitivesYaml(records, "slipfit segmentation", origin));
  spent.leader = since(start);
  if (times)
    *times = spent;
  return summary;
}

}  // namespace slipfit::pipeline::tiling
