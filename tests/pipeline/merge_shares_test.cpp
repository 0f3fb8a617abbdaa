// What the ranks of a tiled run tell each other: a fit travels as bytes and arrives exactly
// (fit_bytes.h), and the merge's tiles are shared out as runs holding each rank's share of the
// points (mergeShares, tile_merge.h).
#include "tiling/fit_bytes.h"
#include "tiling/tile_merge.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

using namespace slipfit;
using namespace slipfit::pipeline::tiling;

namespace {

/// The same bits: a fit that arrives must give the sender's distances, byte for byte.
bool sameBits(double a, double b) {
  return std::memcmp(&a, &b, sizeof(double)) == 0;
}

std::vector<double> numbers(const Primitive& p) {
  std::string bytes;
  packPrimitive(bytes, p);
  std::vector<double> v((bytes.size() - 1) / sizeof(double));
  std::memcpy(v.data(), bytes.data() + 1, v.size() * sizeof(double));
  return v;
}

}  // namespace

TEST(FitBytes, EveryPrimitiveTypeArrivesBitForBit) {
  // Values a text round trip at 15 digits would change, a negative zero and a subnormal.
  const Eigen::Vector3d a(0.1 + 0.2, -0.0, 4.9406564584124654e-324);
  const Eigen::Vector3d b(1.0 / 3.0, std::nextafter(1.0, 2.0), -1e300);
  const std::vector<Primitive> all = {Plane{a, 0.7 / 3.0}, Sphere{b, 2.0 / 7.0},
                                      Cylinder{a, b, 1e-17}, Cone{b, a, 0.3 + 1e-16},
                                      Torus{a, b, 5.0 / 3.0, 1.0 / 9.0}};
  for (const Primitive& p : all) {
    FitResult f;
    f.type = static_cast<PrimitiveType>(p.index());
    f.status = p.index() == 3 ? FitStatus::degenerate : FitStatus::ok;
    f.reason = p.index() == 3 ? "parallel normals" : "";
    f.algebraic = all[(p.index() + 1) % all.size()];
    f.refined = p;
    f.loss_algebraic = 0.1 * static_cast<double>(p.index() + 1);
    f.loss_refined = std::numeric_limits<double>::denorm_min();
    f.rms_distance = 1.0 / 7.0;
    f.max_distance = 3.0 / 7.0;
    f.used_points = (std::size_t{1} << 40) + p.index();
    f.reciprocal_condition = 1e-13;
    f.iterations = 17;
    std::string bytes;
    packFit(bytes, f);
    Unpack in(bytes);
    const FitResult g = unpackFit(in);
    EXPECT_TRUE(in.done());
    EXPECT_EQ(g.type, f.type);
    EXPECT_EQ(g.status, f.status);
    EXPECT_EQ(g.reason, f.reason);
    ASSERT_EQ(g.refined.index(), p.index());
    ASSERT_EQ(g.algebraic.index(), f.algebraic.index());
    const std::vector<double> sent = numbers(f.refined), got = numbers(g.refined);
    ASSERT_EQ(sent.size(), got.size());
    for (std::size_t k = 0; k < sent.size(); ++k)
      EXPECT_TRUE(sameBits(sent[k], got[k])) << "type " << p.index() << " value " << k;
    EXPECT_EQ(numbers(g.algebraic), numbers(f.algebraic));
    for (const auto& [x, y] : {std::pair{f.loss_algebraic, g.loss_algebraic},
                               {f.loss_refined, g.loss_refined},
                               {f.rms_distance, g.rms_distance},
                               {f.max_distance, g.max_distance},
                               {f.reciprocal_condition, g.reciprocal_condition}})
      EXPECT_TRUE(sameBits(x, y));
    EXPECT_EQ(g.used_points, f.used_points);
    EXPECT_EQ(g.iterations, f.iterations);
  }
  // Plane, sphere, cylinder, cone, torus: 4, 4, 7, 7, 8 numbers after the type.
  EXPECT_EQ(numbers(all[0]).size(), 4u);
  EXPECT_EQ(numbers(all[2]).size(), 7u);
  EXPECT_EQ(numbers(all[4]).size(), 8u);
}

TEST(FitBytes, AShortMessageIsAnErrorNotAReadPastItsEnd) {
  std::string bytes;
  packFit(bytes, FitResult{});
  bytes.pop_back();
  Unpack in(bytes);
  EXPECT_THROW(unpackFit(in), slipfit::pipeline::RunError);
}

TEST(MergeShares, EveryTileOnceInRunsOfAboutEachRanksShareOfThePoints) {
  TilingManifest m;
  // 40 tiles of uneven cores: 1,000 to 40,000 points, and some of a few points.
  for (int t = 0; t < 40; ++t) {
    TileInfo info;
    info.key = {t, 0, 0};
    info.core = t % 7 == 3 ? 5 : static_cast<std::uint64_t>(1000 * (1 + (t * 13) % 40));
    m.tiles.push_back(info);
  }
  std::uint64_t all = 0, largest = 0;
  for (const TileInfo& t : m.tiles) {
    all += t.core;
    largest = std::max(largest, t.core);
  }
  for (const int ranks : {1, 2, 3, 7, 40, 64}) {
    const std::vector<std::size_t> first = mergeShares(m, ranks);
    ASSERT_EQ(first.size(), static_cast<std::size_t>(ranks) + 1);
    EXPECT_EQ(first.front(), 0u);
    EXPECT_EQ(first.back(), m.tiles.size());
    for (int r = 0; r < ranks; ++r) {
      ASSERT_LE(first[r], first[r + 1]) << ranks << " ranks";
      std::uint64_t points = 0;
      for (std::size_t t = first[r]; t < first[r + 1]; ++t)
        points += m.tiles[t].core;
      // A rank's share is all / ranks, give or take the tile that crosses each of its ends.
      const double share = static_cast<double>(all) / ranks;
      EXPECT_LE(static_cast<double>(points), share + static_cast<double>(largest))
          << ranks << " ranks, rank " << r;
      if (ranks <= 3)
        EXPECT_GE(static_cast<double>(points), share - static_cast<double>(largest))
            << ranks << " ranks, rank " << r;
    }
  }
}
