#pragma once
/// \file Checks on the files a run reads and the directory it writes, each failure one line that
/// says what is wrong (no such file, a directory, a FIFO, permission denied, ...).

#include <string>

namespace slipfit::pipeline::detail {

/// What errno means for the user: "permission denied", "no space left on the device", ...
std::string errnoText(int error);

/// Throws RunError (prefixed by \a where) unless \a path is an existing regular file this
/// process may read. \a kind names what a directory is not ("a point cloud file").
void checkReadableFile(const std::string& path, const std::string& where, const std::string& kind);

/// Throws RunError unless \a dir is a directory this process may create files in, or can be
/// created (its nearest existing ancestor is a writable directory).
void checkOutputDir(const std::string& dir);

}  // namespace slipfit::pipeline::detail
