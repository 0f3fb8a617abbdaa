// WorkDistribution in one process (no mpirun): every tile is run exactly once, up to `workers`
// at a time, and a failure stops the handing out and names the lowest failing tile.
#include "tiling/work_distribution.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

using slipfit::pipeline::tiling::WorkDistribution;

TEST(WorkDistribution, RunsEveryTileOnceWithAnyNumberOfWorkers) {
  WorkDistribution work;
  ASSERT_TRUE(work.leader());
  for (const int workers : {1, 2, 3, 8}) {
    for (const std::size_t n : {0, 1, 2, 7, 50}) {
      std::vector<std::atomic<int>> calls(n);
      work.forEachTile(n, workers, [&](std::size_t t) { ++calls.at(t); });
      for (std::size_t t = 0; t < n; ++t)
        EXPECT_EQ(calls[t].load(), 1)
            << "tile " << t << " of " << n << ", " << workers << " workers";
    }
  }
}

TEST(WorkDistribution, TwoWorkersRunTwoTilesAtOnce) {
  // Each of the first two tiles waits until the other has started: with one tile at a time this
  // would wait for the timeout and fail.
  WorkDistribution work;
  std::mutex m;
  std::condition_variable cv;
  int started = 0, in_flight = 0, most = 0;
  work.forEachTile(4, 2, [&](std::size_t t) {
    std::unique_lock<std::mutex> lock(m);
    ++started;
    most = std::max(most, ++in_flight);
    cv.notify_all();
    if (t < 2)
      cv.wait_for(lock, std::chrono::seconds(20), [&] { return started >= 2; });
    --in_flight;
  });
  EXPECT_EQ(started, 4);
  EXPECT_EQ(most, 2);
}

TEST(WorkDistribution, AFailureStopsTheHandingOutAndNamesTheLowestFailingTile) {
  WorkDistribution work;
  for (const int workers : {1, 2}) {
    std::atomic<int> calls{0};
    try {
      work.forEachTile(100, workers, [&](std::size_t t) {
        ++calls;
        if (t == 3 || t == 4)
          throw std::runtime_error("tile " + std::to_string(t));
      });
      ADD_FAILURE() << "no exception";
    } catch (const std::runtime_error& e) {
      // Tile 4 may fail first on the other worker, but tile 3 was taken before it and is the
      // lowest once both have ended.
      EXPECT_STREQ(e.what(), "tile 3");
    }
    // Tiles 0-3, and tile 4 when a second worker took it before the stop; never tile 5.
    EXPECT_GE(calls.load(), 4);
    EXPECT_LE(calls.load(), 3 + workers);
  }
}
