#pragma once
/// \file Who runs which tile: one process runs them all; under `mpirun -np N` (a build with MPI,
/// started by mpirun) the N ranks take tiles from a shared counter on rank 0 as each becomes free
/// (MPI_Fetch_and_op: no scheduler of our own), and rank 0 tiles and merges. Within a process,
/// up to `workers` tiles run at a time, each on a thread of its own.

#include <cstddef>
#include <functional>
#include <string>

namespace slipfit::pipeline::tiling {

class WorkDistribution {
 public:
  WorkDistribution();
  ~WorkDistribution();
  WorkDistribution(const WorkDistribution&) = delete;
  WorkDistribution& operator=(const WorkDistribution&) = delete;

  /// This process tiles, merges and reports (rank 0, or the only process).
  bool leader() const { return rank_ == 0; }
  int ranks() const { return size_; }

  /// Calls \a run(t) for the tiles t in [0, n) that this process takes, up to \a workers calls at
  /// a time (each on a thread of its own); every tile is taken by exactly one process. When a
  /// call throws, no further tile is started here and, once the running calls have returned,
  /// the exception of the lowest such tile is rethrown.
  void forEachTile(std::size_t n, int workers, const std::function<void(std::size_t)>& run);

  /// Collective: throws RunError with the first failing rank's message on every rank when any
  /// rank's \a failure is not empty (a barrier otherwise).
  void shareFailure(const std::string& failure);

  /// Collective: the sum of \a value over the ranks.
  std::size_t sum(std::size_t value);

  /// Collective: the leader's \a text, on every rank.
  std::string broadcast(const std::string& text);

 private:
  /// The next tile for this process to run; n when none is left (one thread at a time).
  std::size_t take(std::size_t n);

  int rank_ = 0, size_ = 1;
  bool initialised_here_ = false;
  bool threads_may_share_ = true;  ///< the MPI library allows calls from any one thread at a time
  std::size_t next_ = 0;           ///< the next tile without MPI
  void* window_ = nullptr;         ///< MPI_Win of the shared counter (with MPI)
};

}  // namespace slipfit::pipeline::tiling
