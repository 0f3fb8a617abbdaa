#include "work_distribution.h"

#include "worker_pool.h"

#include "slipfit/pipeline/errors.h"

#include <algorithm>
#include <cstdlib>
#include <new>
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

std::vector<std::string> WorkDistribution::gather(const std::string& text) {
  if (size_ == 1)
    return {text};
  const auto length = static_cast<long long>(text.size());
  std::vector<long long> lengths(static_cast<std::size_t>(size_));
  MPI_Gather(&length, 1, MPI_LONG_LONG, lengths.data(), 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
  constexpr long long kPiece = 1LL << 30;  // MPI counts are int
  if (rank_ != 0) {
    for (long long at = 0; at < length; at += kPiece)
      MPI_Send(text.data() + at, static_cast<int>(std::min(kPiece, length - at)), MPI_CHAR, 0, 0,
               MPI_COMM_WORLD);
    return {};
  }
  std::vector<std::string> all(static_cast<std::size_t>(size_));
  all[0] = text;
  for (int r = 1; r < size_; ++r) {
    std::string& t = all[static_cast<std::size_t>(r)];
    t.assign(static_cast<std::size_t>(lengths[static_cast<std::size_t>(r)]), '\0');
    for (long long at = 0; at < lengths[static_cast<std::size_t>(r)]; at += kPiece)
      MPI_Recv(t.data() + at,
               static_cast<int>(std::min(kPiece, lengths[static_cast<std::size_t>(r)] - at)),
               MPI_CHAR, r, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  }
  return all;
}

std::vector<std::string> WorkDistribution::allGather(const std::string& text) {
  if (size_ == 1)
    return {text};
  const auto length = static_cast<long long>(text.size());
  std::vector<long long> lengths(static_cast<std::size_t>(size_));
  MPI_Allgather(&length, 1, MPI_LONG_LONG, lengths.data(), 1, MPI_LONG_LONG, MPI_COMM_WORLD);
  // Each rank's text in pieces of at most 1 GiB (MPI counts are int).
  constexpr long long kPiece = 1LL << 30;
  std::vector<std::string> all(static_cast<std::size_t>(size_));
  for (int r = 0; r < size_; ++r) {
    std::string& t = all[static_cast<std::size_t>(r)];
    t = r == rank_ ? text : std::string(static_cast<std::size_t>(lengths[r]), '\0');
    for (long long at = 0; at < lengths[r]; at += kPiece)
      MPI_Bcast(t.data() + at, static_cast<int>(std::min(kPiece, lengths[r] - at)), MPI_CHAR, r,
                MPI_COMM_WORLD);
  }
  return all;
}

std::vector<std::uint64_t> WorkDistribution::sumBefore(const std::vector<std::uint64_t>& values) {
  std::vector<std::uint64_t> before(values.size(), 0);
  if (size_ == 1 || values.empty())
    return before;
  MPI_Exscan(values.data(), before.data(), static_cast<int>(values.size()), MPI_UINT64_T, MPI_SUM,
             MPI_COMM_WORLD);
  if (rank_ == 0)  // MPI_Exscan leaves the first rank's result undefined
    std::fill(before.begin(), before.end(), 0);
  return before;
}

std::vector<std::uint64_t> WorkDistribution::sumEach(const std::vector<std::uint64_t>& values) {
  if (size_ == 1 || values.empty())
    return values;
  std::vector<std::uint64_t> total(values.size(), 0);
  MPI_Allreduce(values.data(), total.data(), static_cast<int>(values.size()), MPI_UINT64_T, MPI_SUM,
                MPI_COMM_WORLD);
  return total;
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

std::vector<std::string> WorkDistribution::gather(const std::string& text) {
  return {text};
}

std::vector<std::string> WorkDistribution::allGather(const std::string& text) {
  return {text};
}

std::vector<std::uint64_t> WorkDistribution::sumBefore(const std::vector<std::uint64_t>& values) {
  return std::vector<std::uint64_t>(values.size(), 0);
}

std::vector<std::uint64_t> WorkDistribution::sumEach(const std::vector<std::uint64_t>& values) {
  return values;
}

#endif

void WorkDistribution::together(const std::function<void()>& local) {
  if (size_ == 1) {
    local();
    return;
  }
  std::string failure;
  try {
    local();
  } catch (const std::bad_alloc&) {
    failure = "out of memory";
  } catch (const std::exception& e) {
    failure = e.what();
  }
  shareFailure(failure);
}

void WorkDistribution::forEachTile(std::size_t n, int workers,
                                   const std::function<void(std::size_t)>& run) {
  next_ = 0;
  runOnWorkers(
      n, threads_may_share_ ? workers : 1, [&] { return take(n); }, run);
}

}  // namespace slipfit::pipeline::tiling
