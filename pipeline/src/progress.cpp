#include "slipfit/pipeline/progress.h"

#include <unistd.h>

#include <cstdio>

namespace slipfit::pipeline {

Progress::Progress(bool enabled) : enabled_(enabled && ::isatty(STDERR_FILENO) == 1) {}

void Progress::begin(std::size_t index, std::size_t count, const std::string& label) {
  label_ = label;
  index_ = index;
  count_ = count;
  noted_ = false;
  start_ = std::chrono::steady_clock::now();
  if (enabled_)
    std::fprintf(stderr, "[%zu/%zu] %s ...", index, count, label.c_str());
  if (enabled_)
    std::fflush(stderr);
}

void Progress::note(const std::string& detail) {
  if (!enabled_)
    return;
  // Carriage return and erase-to-end-of-line: the step's line, now with what it is doing.
  std::fprintf(stderr, "\r\033[K[%zu/%zu] %s: %s ...", index_, count_, label_.c_str(),
               detail.c_str());
  std::fflush(stderr);
  noted_ = true;
}

void Progress::end() {
  if (enabled_ && noted_)
    std::fprintf(stderr, "\r\033[K[%zu/%zu] %s ...", index_, count_, label_.c_str());
  if (enabled_)
    std::fprintf(stderr, " %.2f s\n", elapsed());
  noted_ = false;
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
