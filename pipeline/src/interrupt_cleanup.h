#pragma once
/// \file SIGINT and SIGTERM during a run: the temporary output files are removed and the process
/// exits with 128 + the signal's number (130, 143), as a shell reports an interrupted command.

#include <string>

namespace slipfit::pipeline::detail {

/// Installs the handlers (once; later calls do nothing).
void installInterruptCleanup();

/// A file the handler removes if a signal arrives; returns a slot for releaseTemporary, or -1
/// when every slot is taken (the file is then removed only by the normal paths).
int registerTemporary(const std::string& path);
void releaseTemporary(int slot);

/// Creates a new file (O_EXCL: never an existing file, never through a symlink) at \a prefix +
/// six random characters + \a suffix, registered *before* it exists, so that no signal can come
/// between its creation and its registration and leave it behind. Returns the descriptor (or −1,
/// errno set) and sets \a path and \a slot.
int createTemporary(const std::string& prefix, const std::string& suffix, std::string& path,
                    int& slot);

/// After the renames of a commit: a later signal no longer says that nothing was written.
void noteOutputsCommitted();

}  // namespace slipfit::pipeline::detail
