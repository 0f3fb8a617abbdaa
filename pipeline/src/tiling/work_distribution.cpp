#include "work_distribution.h"

#include "worker_pool.h"

#include "slipfit/pipeline/errors.h"

#include <cstdlib>
#include <vector>

#ifdef SLIPFIT_WITH_MPI
#include <mpi.h>
#endif

namespace slipfit::pipeline::tiling {

#ifdef SLIPFIT_WITH_MPI

namespace {
/// Started by mpirun (Open MPI sets OMPI_COMM_WORLD_SIZE; PMI launchers PMI_SIZE / PMIX_RANK).
bool launchedByMpirun() {
  return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE") || std::getenv("PMIX_RANK");
}
}  // namespace

WorkDistribution::WorkDistribution() {
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (!initialised) {
    if (!launchedByMpirun())
      return;
    int provided = MPI_THREAD_SINGLE;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
    initialised_here_ = true;
  }
  int level = MPI_THREAD_SINGLE;
  MPI_Query_thread(&level);
  threads_may_share_ = level >= MPI_THREAD_SERIALIZED;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  if (size_ == 1)
    return;
  auto* window = new MPI_Win;
  long* counter = nullptr;
  MPI_Win_allocate(rank_ == 0 ? sizeof(long) : 0, sizeof(long), MPI_INFO_NULL, MPI_COMM_WORLD,
                   &counter, window);
  if (rank_ == 0) {
    MPI_Win_lock(MPI_LOCK_EXCLUSIVE, 0, 0, *window);
    *counter = 0;
    MPI_Win_unlock(0, *window);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  window_ = window;
}

WorkDistribution::~WorkDistribution() {
  if (window_) {
    auto* window = static_cast<MPI_Win*>(window_);
    MPI_Win_free(window);
    delete window;
  }
  if (initialised_here_)
    MPI_Finalize();
}

std::size_t WorkDistribution::take(std::size_t n) {
  if (!window_)
    return next_ < n ? next_++ : n;
  auto& window = *static_cast<MPI_Win*>(window_);
  const long one = 1;
  long taken = 0;
  MPI_Win_lock(MPI_LOCK_SHARED, 0, 0, window);
  MPI_Fetch_and_op(&one, &taken, MPI_LONG, 0, 0, MPI_SUM, window);
  MPI_Win_unlock(0, window);
  return taken < 0 || static_cast<std::size_t>(taken) >= n ? n : static_cast<std::size_t>(taken);
}

void WorkDistribution::shareFailure(const std::string& failure) {
  if (size_ == 1) {
    if (!failure.empty())
      throw RunError(failure);
    return;
  }
  int mine = failure.empty() ? size_ : rank_, first = size_;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (first == size_)
    return;
  int length = static_cast<int>(failure.size());
  MPI_Bcast(&length, 1, MPI_INT, first, MPI_COMM_WORLD);
  std::vector<char> text(failure.begin(), failure.end());
  text.resize(static_cast<std::size_t>(length));
  MPI_Bcast(text.data(), length, MPI_CHAR, first, MPI_COMM_WORLD);
  throw RunError(std::string(text.begin(), text.end()) +
                 (first == 0 ? "" : " (rank " + std::to_string(first) + ")"));
}

std::size_t WorkDistribution::sum(std::size_t value) {
  if (size_ == 1)
    return value;
  unsigned long long mine = value, total = 0;
  MPI_Allreduce(&mine, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  return static_cast<std::size_t>(total);
}

std::string WorkDistribution::broadcast(const std::string& text) {
  if (size_ == 1)
    return text;
  unsigned long long length = text.size();
  MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
  std::vector<char> buffer(text.begin(), text.end());
  buffer.resize(static_cast<std::size_t>(length));
  MPI_Bcast(buffer.data(), static_cast<int>(length), MPI_CHAR, 0, MPI_COMM_WORLD);
  return std::string(buffer.begin(), buffer.end());
}

#else  // one process

WorkDistribution::WorkDistribution() = default;
WorkDistribution::~WorkDistribution() = default;

std::size_t WorkDistribution::take(std::size_t n) {
  return next_ < n ? next_++ : n;
}

void WorkDistribution::shareFailure(const std::string& failure) {
  if (!failure.empty())
    throw RunError(failure);
}

std::size_t WorkDistribution::sum(std::size_t value) {
  return value;
}

std::string WorkDistribution::broadcast(const std::string& text) {
  return text;
}

#endif

void WorkDistribution::forEachTile(std::size_t n, int workers,
                                   const std::function<void(std::size_t)>& run) {
  next_ = 0;
  runOnWorkers(
      n, threads_may_share_ ? workers : 1, [&] { return take(n); }, run);
}

}  // namespace slipfit::pipeline::tiling
