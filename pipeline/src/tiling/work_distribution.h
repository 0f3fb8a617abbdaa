#pragma once
/// \file Who runs which tile: one process runs them all; under `mpirun -np N` (a build with MPI,
/// started by mpirun) the N ranks take tiles from a shared counter on rank 0 as each becomes free
/// (MPI_Fetch_and_op: no scheduler of our own); the ranks tile and merge together, each its share
/// of the rows or tiles, and rank 0 reduces what they found and reports. Within a process, up to
/// `workers` tiles run at a time, each on a thread of its own.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace slipfit::pipeline::tiling {

class WorkDistribution {
 public:
  WorkDistribution();
  ~WorkDistribution();
  WorkDistribution(const WorkDistribution&) = delete;
  WorkDistribution& operator=(const WorkDistribution&) = delete;

  /// This process claims the work directory, adds up what the ranks found and writes the outputs
  /// (rank 0, or the only process).
  bool leader() const { return rank_ == 0; }
  int rank() const { return rank_; }
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

  /// Collective: runs \a local on this rank; with other ranks, its failure is shared (RunError
  /// with the first failing rank's message on every rank), so that no rank waits for one that
  /// has given up. Alone, \a local's exceptions pass as they are.
  void together(const std::function<void()>& local);

  /// Collective: every rank's \a text, in rank order, on the leader (empty elsewhere).
  std::vector<std::string> gather(const std::string& text);

  /// Collective: every rank's \a text, in rank order, on every rank.
  std::vector<std::string> allGather(const std::string& text);

  /// Collective: for each k, the sum of \a values[k] over the ranks before this one (zeros on the
  /// first); every rank gives as many values.
  std::vector<std::uint64_t> sumBefore(const std::vector<std::uint64_t>& values);

  /// Collective: the ranks' \a values summed element by element, on every rank.
  std::vector<std::uint64_t> sumEach(const std::vector<std::uint64_t>& values);

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
