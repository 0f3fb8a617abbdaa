#pragma once
/// \file Progress on a terminal, silence when piped or with --quiet.

#include <chrono>
#include <cstddef>
#include <string>

namespace slipfit::pipeline {

class Progress {
 public:
  /// Enabled only when \a enabled and standard error is a terminal.
  explicit Progress(bool enabled);
  bool enabled() const { return enabled_; }
  /// Starts step \a index of \a count.
  void begin(std::size_t index, std::size_t count, const std::string& label);
  /// Names what the current step is doing now ("merge_regions"): the step's line is rewritten
  /// in place with it.
  void note(const std::string& detail);
  /// Ends the current step.
  void end();
  /// A whole line for a piece of step \a index that took \a seconds (pieces that run at the same
  /// time are reported as each ends; the caller serialises the calls).
  void step(std::size_t index, std::size_t count, const std::string& label, double seconds);
  /// Seconds since begin().
  double elapsed() const;

 private:
  bool enabled_ = false;
  std::size_t index_ = 0, count_ = 0;
  bool noted_ = false;
  std::string label_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace slipfit::pipeline
