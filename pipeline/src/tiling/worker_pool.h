#pragma once
/// \file Independent pieces of work (tiles) on a few threads of one process: each thread takes
/// the next piece until none is left. Used for the tiles' runs (the pieces a process takes) and
/// for the merge's passes over the tiles.

#include <cstddef>
#include <functional>

namespace slipfit::pipeline::tiling {

/// Calls \a run(t) for every t that \a take returns until it returns \a n, on up to \a workers
/// threads (the caller's among them; \a take is called by one thread at a time). When a call
/// throws, no thread takes another piece and, once the running calls have returned, the
/// exception of the lowest such t is rethrown.
void runOnWorkers(std::size_t n, int workers, const std::function<std::size_t()>& take,
                  const std::function<void(std::size_t)>& run);

/// runOnWorkers() over t = 0, 1, …, n − 1.
void forEachOnWorkers(std::size_t n, int workers, const std::function<void(std::size_t)>& run);

}  // namespace slipfit::pipeline::tiling
