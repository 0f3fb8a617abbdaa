#pragma once
/// \file Who runs which tile: one process runs them all in order; under `mpirun -np N` (a build
/// with MPI, started by mpirun) the N ranks take tiles from a shared counter on rank 0 as each
/// becomes free (MPI_Fetch_and_op: no scheduler of our own), and rank 0 tiles and merges.

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

  /// Calls \a run(t) for the tiles t in [0, n) that this process takes; every tile is taken by
  /// exactly one process.
  void forEachTile(std::size_t n, const std::function<void(std::size_t)>& run);

  /// Collective: throws RunError with the first failing rank's message on every rank when any
  /// rank's \a failure is not empty (a barrier otherwise).
  void shareFailure(const std::string& failure);

  /// Collective: the sum of \a value over the ranks.
  std::size_t sum(std::size_t value);

 private:
  int rank_ = 0, size_ = 1;
  bool initialised_here_ = false;
  void* window_ = nullptr;  ///< MPI_Win of the shared counter (with MPI)
};

}  // namespace slipfit::pipeline::tiling
