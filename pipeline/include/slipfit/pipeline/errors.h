#pragma once
/// \file The two kinds of failure the command line tells apart by exit code.

#include <stdexcept>
#include <string>

namespace slipfit::pipeline {

/// A usage or configuration mistake (exit code 2): unknown stage or key, bad value, bad --set.
/// The message already names the place (file:line:column, stage tag, key).
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A failure while running (exit code 1): unreadable or invalid input data, a stage that cannot
/// compute, an output that cannot be written.
class RunError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// An option value that does not convert or is out of range; the config layer adds the place.
class OptionValueError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace slipfit::pipeline
