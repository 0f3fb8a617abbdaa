#pragma once
/// \file The one rule for a thread count, shared by every parallel stage and the tiled run: 0
/// means as many as the machine has, a positive count is used as given, a negative one is an
/// error. Results never depend on the count (each parallel loop writes per-item slots).

#include <string>

namespace slipfit {

/// Throws InvalidParameterError "<owner>: threads = N violates 'threads >= 0 (0: all cores)'"
/// when \a threads is negative.
void validateThreads(int threads, const std::string& owner);

/// The OpenMP thread count for \a threads (validated as validateThreads does): the machine's
/// processor count for 0, \a threads otherwise.
int resolveThreads(int threads);

}  // namespace slipfit
