#include "worker_pool.h"

#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace slipfit::pipeline::tiling {

void runOnWorkers(std::size_t n, int workers, const std::function<std::size_t()>& take,
                  const std::function<void(std::size_t)>& run) {
  std::mutex mutex;  // guards take, failed and failure
  std::size_t failed = n;
  std::exception_ptr failure;
  std::atomic<bool> stop{false};
  const auto work = [&] {
    while (!stop) {
      std::size_t t = n;
      {
        const std::lock_guard<std::mutex> lock(mutex);
        t = take();
      }
      if (t >= n)
        return;
      try {
        run(t);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(mutex);
        if (t < failed) {
          failed = t;
          failure = std::current_exception();
        }
        stop = true;
      }
    }
  };
  std::vector<std::thread> threads;
  for (int w = 1; w < workers && static_cast<std::size_t>(w) < n; ++w)
    threads.emplace_back(work);
  work();
  for (auto& thread : threads)
    thread.join();
  if (failure)
    std::rethrow_exception(failure);
}

void forEachOnWorkers(std::size_t n, int workers, const std::function<void(std::size_t)>& run) {
  std::size_t next = 0;
  runOnWorkers(
      n, workers, [&] { return next < n ? next++ : n; }, run);
}

}  // namespace slipfit::pipeline::tiling
