#include "slipfit/pipeline/progress.h"

#include <unistd.h>

#include <cstdio>

namespace slipfit::pipeline {

Progress::Progress(bool enabled) : enabled_(enabled && ::isatty(STDERR_FILENO) == 1) {}

void Progress::begin(std::size_t index, std::size_t count, const std::string& label) {
  label_ = label;
  start_ = std::chrono::steady_clock::now();
  if (enabled_)
    std::fprintf(stderr, "[%zu/%zu] %s ...", index, count, label.c_str());
  if (enabled_)
    std::fflush(stderr);
}

void Progress::end() {
  if (enabled_)
    std::fprintf(stderr, " %.2f s\n", elapsed());
}

void Progress::step(std::size_t index, std::size_t count, const std::string& label,
                    double seconds) {
  if (enabled_)
    std::fprintf(stderr, "[%zu/%zu] %s ... %.2f s\n", index, count, label.c_str(), seconds);
}

double Progress::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

}  // namespace slipfit::pipeline
