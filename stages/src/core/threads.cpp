#include "slipfit/core/threads.h"

#include "slipfit/core/exceptions.h"

#include <omp.h>

namespace slipfit {

void validateThreads(int threads, const std::string& owner) {
  if (threads < 0)
    throw InvalidParameterError(owner + ": threads = " + std::to_string(threads) +
                                " violates 'threads >= 0 (0: all cores)'");
}

int resolveThreads(int threads) {
  validateThreads(threads, "threads");
  return threads > 0 ? threads : omp_get_num_procs();
}

}  // namespace slipfit
