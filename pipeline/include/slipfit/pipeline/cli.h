#pragma once
/// \file The `slipfit` command line: run, validate, stages, describe.

#include <iosfwd>
#include <string>
#include <vector>

namespace slipfit::pipeline {

/// Exit codes of the command line.
enum ExitCode : int { kSuccess = 0, kRunFailure = 1, kUsageError = 2 };

/// Runs the command line on \a args (without the program name). Reports go to \a out, errors
/// (one line each) to \a err.
int runCommandLine(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace slipfit::pipeline
