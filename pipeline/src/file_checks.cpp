#include "file_checks.h"

#include "slipfit/pipeline/errors.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace slipfit::pipeline::detail {

namespace fs = std::filesystem;

std::string errnoText(int error) {
  switch (error) {
    case EACCES:
    case EPERM:
      return "permission denied";
    case ENOSPC:
    case EDQUOT:
      return "no space left on the device (disk full or quota reached)";
    case EROFS:
      return "read-only file system";
    default:
      return std::strerror(error);
  }
}

void checkReadableFile(const std::string& path, const std::string& where, const std::string& kind) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory)
    throw RunError(where + errnoText(ec.value()));
  if (!fs::exists(status))
    throw RunError(where + "no such file");
  if (fs::is_directory(status))
    throw RunError(where + "is a directory, not " + kind);
  if (!fs::is_regular_file(status))
    throw RunError(where +
                   "not a regular file (a FIFO, socket or device would block or never end)");
  // A regular file: opening it cannot block.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0)
    throw RunError(where + "cannot be opened: " + errnoText(errno));
  ::close(fd);
}

void checkOutputDir(const std::string& dir) {
  const std::string where = "output.dir '" + dir + "': ";
  fs::path at = dir.empty() ? fs::path(".") : fs::path(dir);
  std::error_code ec;
  // The nearest existing ancestor decides: the directory itself, or where it will be created.
  while (!fs::exists(at, ec)) {
    if (ec && ec != std::errc::no_such_file_or_directory && ec != std::errc::not_a_directory)
      throw RunError(where + errnoText(ec.value()));
    const fs::path parent = at.has_relative_path() ? at.parent_path() : at;
    if (parent.empty()) {
      at = ".";
      break;
    }
    if (parent == at)
      break;
    at = parent;
  }
  if (!fs::is_directory(at, ec))
    throw RunError(where + (at == fs::path(dir) ? std::string("not a directory")
                                                : "'" + at.string() + "' is not a directory"));
  if (::access(at.c_str(), W_OK | X_OK) != 0)
    throw RunError(where + errnoText(errno) +
                   (at == fs::path(dir) ? std::string(" (cannot create files in it)")
                                        : " (cannot create it in '" + at.string() + "')"));
}

}  // namespace slipfit::pipeline::detail
