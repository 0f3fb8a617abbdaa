#pragma once
/// \file The work directory of a tiled run (tiling.workdir, or <output.dir>/tiles) is slipfit's
/// own, and only one run's at a time:
/// - slipfit claims a new or empty directory by writing its marker (.slipfit-workdir) first; a
///   directory that is not empty and has no marker is refused, whatever it holds;
/// - a run holds an exclusive lock (flock on .slipfit-lock, which names its process) until it
///   ends; a second run on the directory is refused in one line, and a lock left by a killed run
///   is gone with its process;
/// - slipfit removes only the files of its own layout (manifest.yaml, analysis,
///   tiles/tile_<i>_<j>.ply, runs/config, runs/analysis, runs/tile_<i>_<j>/): a file of any
///   other name stays where it is;
/// - the input never lies inside the work directory (compared by device and inode, through
///   symbolic links): a tiled run rewrites what is there.
/// Each run writes a fresh token (.slipfit-run): the ranks of an MPI run compare it with the
/// leader's to know that they all see the same directory.

#include <string>

namespace slipfit::pipeline::tiling {

/// Throws RunError unless \a dir can be the work directory of a run that reads \a input: new,
/// empty or marked as slipfit's, and \a input not inside it. `validate` and `run` both check it.
void checkWorkDirectory(const std::string& dir, const std::string& input);

/// A work directory claimed and locked for the lifetime of the object (by the run's leader).
class WorkDirectory {
 public:
  /// Checks \a dir as checkWorkDirectory does, creates it and its marker when new or empty, takes
  /// the lock and writes a new token. Throws RunError.
  WorkDirectory(std::string dir, const std::string& input);
  /// Releases the lock; a directory this object created that holds nothing but slipfit's own
  /// marker, lock and token (a run that failed before its first tile) is removed.
  ~WorkDirectory();
  WorkDirectory(const WorkDirectory&) = delete;
  WorkDirectory& operator=(const WorkDirectory&) = delete;

  const std::string& path() const { return dir_; }
  /// This run's token (also in the directory, for the other ranks).
  const std::string& token() const { return token_; }

  /// Removes the tiles and everything computed from them (the tiling's own files only).
  void removeTiling() const;
  /// Removes the tiles' runs (the tiling's own files only) and leaves runs/ empty.
  void removeRuns() const;

 private:
  std::string dir_, token_;
  int lock_fd_ = -1;
  bool created_ = false;
};

/// The token the leader wrote in \a dir ("" when there is none).
std::string readRunToken(const std::string& dir);

/// Whether \a name is a tile's file or run directory name ("tile_<i>_<j>" or
/// "tile_<i>_<j>_<level>", with \a suffix).
bool isTileName(const std::string& name, const std::string& suffix);

}  // namespace slipfit::pipeline::tiling
