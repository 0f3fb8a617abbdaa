#pragma once
/// \file Runs the built `slipfit` executable as a user would and captures its exit code, standard
/// output and standard error.

#include "paths.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace slipfit::testing {

struct CliResult {
  int code = -1;
  std::string out;
  std::string err;
};

inline std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Runs `slipfit ARGS` (a shell-quoted string) with the source tree as working directory, after
/// the shell commands \a prefix (e.g. "ulimit -f 20;"), through \a wrapper if given (e.g.
/// "/usr/bin/time -f %M -o FILE").
inline CliResult runSlipfit(const std::string& args, const std::string& prefix = "",
                            const std::string& wrapper = "") {
  namespace fs = std::filesystem;
  fs::create_directories(kScratchDir);
  static int counter = 0;
  const std::string base = std::string(kScratchDir) + "/cli" + std::to_string(::getpid()) + "_" +
                           std::to_string(counter++);
  const std::string command = prefix + std::string("cd '") + kSourceDir + "' && " + wrapper + " '" +
                              kSlipfitExe + "' " + args + " > '" + base + ".out' 2> '" + base +
                              ".err' < /dev/null";
  const int status = std::system(command.c_str());
  CliResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(base + ".out");
  r.err = slurp(base + ".err");
  fs::remove(base + ".out");
  fs::remove(base + ".err");
  return r;
}

/// This process's scratch directory: ctest runs tests in parallel, each in its own process. It is
/// emptied on first use: an earlier process with the same pid (pids are reused) may have left
/// files of the same names.
inline std::string processScratch() {
  static const std::string dir = [] {
    const std::string path = std::string(kScratchDir) + "/p" + std::to_string(::getpid());
    std::filesystem::remove_all(path);
    return path;
  }();
  std::filesystem::create_directories(dir);
  return dir;
}

/// Writes \a text to a scratch file \a name and returns its absolute path.
inline std::string scratchFile(const std::string& name, const std::string& text) {
  const std::string path = processScratch() + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

/// A fresh, empty scratch directory.
inline std::string scratchDir(const std::string& name) {
  const std::string path = processScratch() + "/" + name;
  std::filesystem::remove_all(path);
  return path;
}

}  // namespace slipfit::testing
