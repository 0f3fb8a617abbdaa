#pragma once
/// \file All-or-nothing outputs: every file is written under a temporary name in the output
/// directory and renamed into place only when the whole run has succeeded.

#include <functional>
#include <string>
#include <vector>

namespace slipfit::pipeline {

class OutputFiles {
 public:
  explicit OutputFiles(std::string dir) : dir_(std::move(dir)) {}
  OutputFiles(const OutputFiles&) = delete;
  OutputFiles& operator=(const OutputFiles&) = delete;
  /// Removes the temporary files of an uncommitted run.
  ~OutputFiles();

  /// A file no output may replace (the input cloud): add() refuses a name that is it.
  void protect(const std::string& path) { protected_.push_back(path); }
  /// Creates the directory if needed and calls \a write with a temporary path next to \a name.
  /// Throws RunError when the directory cannot be created, the final path is a protected file,
  /// or \a write fails.
  void add(const std::string& name, const std::function<void(const std::string& path)>& write);
  /// add() for a text file.
  void addText(const std::string& name, const std::string& text);
  /// Renames every temporary file to its final name; returns the final paths.
  std::vector<std::string> commit();

 private:
  std::string dir_;
  std::vector<std::string> protected_;
  std::vector<std::pair<std::string, std::string>> pending_;  // temporary, final
};

}  // namespace slipfit::pipeline
