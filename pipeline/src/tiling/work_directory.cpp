#include "work_directory.h"

#include "../file_checks.h"

#include "slipfit/pipeline/errors.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

namespace slipfit::pipeline::tiling {

namespace fs = std::filesystem;

namespace {

constexpr const char* kMarker = ".slipfit-workdir";
constexpr const char* kMarkerText = "slipfit work directory 1\n";
constexpr const char* kLock = ".slipfit-lock";
constexpr const char* kToken = ".slipfit-run";

std::string where(const std::string& dir) {
  return "tiling.workdir '" + dir + "': ";
}

/// Whether \a path lies inside \a dir (or is it), by device and inode through links.
bool inside(const std::string& path, const std::string& dir) {
  std::error_code ec;
  fs::path at = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec)
    return false;
  for (;;) {
    if (fs::equivalent(at, dir, ec))
      return true;
    const fs::path parent = at.parent_path();
    if (parent == at || parent.empty())
      return false;
    at = parent;
  }
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Removes the file \a path when it is there; RunError when it cannot be removed.
void removeFile(const fs::path& path) {
  std::error_code ec;
  fs::remove(path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory)
    throw RunError("'" + path.string() + "': cannot be removed: " + detail::errnoText(ec.value()));
}

/// Removes \a dir when it is empty.
void removeIfEmpty(const fs::path& dir) {
  std::error_code ec;
  if (fs::is_directory(fs::symlink_status(dir, ec)) && fs::is_empty(dir, ec))
    fs::remove(dir, ec);
}

}  // namespace

bool isTileName(const std::string& name, const std::string& suffix) {
  if (name.size() <= suffix.size() ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0 ||
      name.rfind("tile_", 0) != 0)
    return false;
  const std::string keys = name.substr(5, name.size() - 5 - suffix.size());
  // tile_<i>_<j>, or tile_<i>_<j>_<level> for a quarter of a split tile (level ≥ 1)
  int numbers = 0;
  std::size_t at = 0;
  while (at <= keys.size()) {
    std::size_t end = keys.find('_', at);
    if (end == std::string::npos)
      end = keys.size();
    std::string number = keys.substr(at, end - at);
    if (!number.empty() && number[0] == '-' && numbers < 2)
      number.erase(0, 1);
    if (number.empty() || number.find_first_not_of("0123456789") != std::string::npos)
      return false;
    ++numbers;
    at = end + 1;
  }
  return numbers == 2 || numbers == 3;
}

void checkWorkDirectory(const std::string& dir, const std::string& input) {
  std::error_code ec;
  const fs::file_status status = fs::status(dir, ec);
  if (!fs::exists(status))
    return;  // created by the run
  if (!fs::is_directory(status))
    throw RunError(where(dir) + "is not a directory");
  if (!input.empty() && inside(input, dir))
    throw RunError(where(dir) + "holds the input '" + input +
                   "', and a tiled run rewrites what is there; move the input or give another "
                   "tiling.workdir");
  if (!fs::is_empty(dir, ec) && !fs::is_regular_file(fs::path(dir) / kMarker))
    throw RunError(where(dir) +
                   "not a slipfit work directory (no .slipfit-workdir in it) and not empty; give "
                   "an empty or new one");
  if (fs::is_regular_file(fs::path(dir) / kMarker) &&
      readFile((fs::path(dir) / kMarker).string()) != kMarkerText)
    throw RunError(where(dir) + ".slipfit-workdir is not slipfit's marker");
}

WorkDirectory::WorkDirectory(std::string dir, const std::string& input) : dir_(std::move(dir)) {
  checkWorkDirectory(dir_, input);
  std::error_code ec;
  created_ = !fs::exists(dir_, ec);
  fs::create_directories(dir_, ec);
  if (ec)
    throw RunError(where(dir_) + "cannot be created: " + detail::errnoText(ec.value()));
  const fs::path marker = fs::path(dir_) / kMarker;
  if (!fs::exists(marker)) {
    // The marker goes in first, into an empty directory (checked again: it is ours from here).
    if (!fs::is_empty(dir_, ec))
      throw RunError(where(dir_) + "is not empty; give an empty or new one");
    std::ofstream out(marker, std::ios::trunc);
    out << kMarkerText;
    out.close();
    if (!out)
      throw RunError(where(dir_) + "write failed (disk full?)");
  }
  const std::string lock_path = (fs::path(dir_) / kLock).string();
  lock_fd_ = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (lock_fd_ < 0)
    throw RunError(where(dir_) + "cannot create its lock: " + detail::errnoText(errno));
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    std::string holder = readFile(lock_path);
    while (!holder.empty() && holder.back() == '\n')
      holder.pop_back();
    ::close(lock_fd_);
    lock_fd_ = -1;
    if (error == EWOULDBLOCK)
      throw RunError(where(dir_) + "in use by another slipfit run" +
                     (holder.empty() ? std::string() : " (" + holder + ")") +
                     "; wait for it to end or give another tiling.workdir");
    throw RunError(where(dir_) + "cannot be locked: " + detail::errnoText(error));
  }
  char host[256] = "";
  ::gethostname(host, sizeof host - 1);
  const std::string holder = "process " + std::to_string(::getpid()) + " on " + host + "\n";
  if (::ftruncate(lock_fd_, 0) != 0 ||
      ::write(lock_fd_, holder.data(), holder.size()) != static_cast<ssize_t>(holder.size()))
    throw RunError(where(dir_) + "write failed (disk full?)");
  // A token that no earlier run wrote: random bits, the process and the time.
  std::random_device random;
  std::ostringstream token;
  token << std::hex << random() << random() << "-" << ::getpid() << "-"
        << std::chrono::steady_clock::now().time_since_epoch().count();
  token_ = token.str();
  const std::string token_path = (fs::path(dir_) / kToken).string();
  std::ofstream out(token_path, std::ios::trunc);
  out << token_ << "\n";
  out.close();
  if (!out)
    throw RunError(where(dir_) + "write failed (disk full?)");
}

WorkDirectory::~WorkDirectory() {
  if (created_) {
    std::error_code ec;
    bool only_ours = true;
    for (const auto& e : fs::directory_iterator(dir_, ec)) {
      const std::string name = e.path().filename().string();
      only_ours = only_ours && (name == kMarker || name == kLock || name == kToken);
    }
    if (only_ours && !ec)
      for (const char* name : {kToken, kLock, kMarker})
        fs::remove(fs::path(dir_) / name, ec);
    removeIfEmpty(dir_);
  }
  if (lock_fd_ >= 0)
    ::close(lock_fd_);  // releases the flock
}

void WorkDirectory::removeTiling() const {
  const fs::path dir(dir_);
  for (const char* name : {"manifest.yaml", "manifest.yaml.tmp", "analysis", "analysis.tmp"})
    removeFile(dir / name);
  std::error_code ec;
  if (fs::is_directory(fs::symlink_status(dir / "tiles", ec)))
    for (const auto& e : fs::directory_iterator(dir / "tiles"))
      if (isTileName(e.path().filename().string(), ".ply") && !e.is_directory())
        removeFile(e.path());
  removeIfEmpty(dir / "tiles");
  removeRuns();
  removeIfEmpty(dir / "runs");
}

void WorkDirectory::removeRuns() const {
  const fs::path runs = fs::path(dir_) / "runs";
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(runs, ec)))
    return;
  for (const char* name : {"config", "config.tmp", "analysis", "analysis.tmp"})
    removeFile(runs / name);
  for (const auto& e : fs::directory_iterator(runs)) {
    if (!isTileName(e.path().filename().string(), "") ||
        !fs::is_directory(fs::symlink_status(e.path(), ec)))
      continue;
    // A tile's run directory holds the files of its run alone (symbolic links are removed, not
    // followed).
    for (const auto& f : fs::directory_iterator(e.path()))
      if (!fs::is_directory(fs::symlink_status(f.path(), ec)))
        removeFile(f.path());
    removeIfEmpty(e.path());
  }
}

std::string readRunToken(const std::string& dir) {
  std::string token = readFile((fs::path(dir) / kToken).string());
  while (!token.empty() && token.back() == '\n')
    token.pop_back();
  return token;
}

}  // namespace slipfit::pipeline::tiling
