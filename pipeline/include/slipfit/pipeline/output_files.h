#pragma once
/// \file All-or-nothing outputs: every file is written under a temporary name in the output
/// directory and renamed into place only when the whole run has succeeded. A temporary name says
/// whose it is: `.<stem>.tmp.<host>-<pid>.<6 random characters><extension>` (and `.previous`
/// after it for a replaced output kept aside during a commit), so that the next run in the
/// directory can recognise what a killed run (SIGKILL, a power cut) left behind.

#include <functional>
#include <string>
#include <vector>

namespace slipfit::pipeline {

/// Removes from \a dir the temporary files that a run on this host left when it was killed (its
/// process is gone); an output kept aside by a commit that was cut short is put back at its name
/// when that name is empty. Files of live processes, of other hosts, of other users, or of other
/// names are left alone, and so is \a input (the run's input, whatever its name). Returns what
/// was done, one entry a file ("removed .segments.tmp....").
std::vector<std::string> removeLeftovers(const std::string& dir, const std::string& input);

class OutputFiles {
 public:
  explicit OutputFiles(std::string dir) : dir_(std::move(dir)) {}
  OutputFiles(const OutputFiles&) = delete;
  OutputFiles& operator=(const OutputFiles&) = delete;
  /// Removes the temporary files of an uncommitted run.
  virtual ~OutputFiles();

  /// A file no output may replace (the input cloud): add() refuses a name that is it.
  void protect(const std::string& path) { protected_.push_back(path); }
  /// Creates the directory if needed and calls \a write with a temporary path next to \a name:
  /// a fresh file created exclusively (mkstemps: no existing file or symlink is followed) and
  /// removed on SIGINT/SIGTERM. Throws RunError when the directory cannot be created, the
  /// final path is a protected file or already an output of this run, or \a write fails.
  void add(const std::string& name, const std::function<void(const std::string& path)>& write);
  /// add() for a text file.
  void addText(const std::string& name, const std::string& text);
  /// Renames every temporary file to its final name, all or none: each temporary file is checked
  /// first (still the regular file created for it, no final name a directory), files already at
  /// the final names are kept aside until every rename has succeeded and put back if one fails.
  /// SIGINT/SIGTERM wait until it is done. Returns the final paths.
  std::vector<std::string> commit();
  /// Whether commit() tells the interrupt handler that the run's outputs are written (default);
  /// off for outputs that are pieces of a larger run.
  void announceCommit(bool announce) { announce_commit_ = announce; }

 protected:
  /// rename(2); a test replaces it to make one rename fail.
  virtual int renameFile(const char* from, const char* to);

 private:
  struct Pending {
    std::string tmp, final_path;
    unsigned long long device = 0, inode = 0;  // of the file mkstemps created
    int slot = -1;                             // in the interrupt cleanup's list
  };
  /// Throws RunError unless the temporary file is still the regular file created for it.
  void checkStillOurs(const Pending& p) const;

  std::string dir_;
  std::vector<std::string> protected_;
  std::vector<Pending> pending_;
  bool announce_commit_ = true;
};

}  // namespace slipfit::pipeline
