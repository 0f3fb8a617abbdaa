#include "slipfit/pipeline/output_files.h"

#include "slipfit/pipeline/errors.h"

#include "digest.h"
#include "file_checks.h"
#include "interrupt_cleanup.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <system_error>

namespace slipfit::pipeline {

namespace fs = std::filesystem;

namespace {

/// The mode a new file gets from open(2) with 0666 and the process's umask.
mode_t defaultFileMode() {
  static const mode_t mode = [] {
    const mode_t mask = ::umask(0);
    ::umask(mask);
    return static_cast<mode_t>(0666 & ~mask);
  }();
  return mode;
}

/// SIGINT/SIGTERM held back while the renames run, so that the commit is never cut in half.
class SignalsHeld {
 public:
  SignalsHeld() {
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    ::pthread_sigmask(SIG_BLOCK, &set, &previous_);
  }
  ~SignalsHeld() { ::pthread_sigmask(SIG_SETMASK, &previous_, nullptr); }
  SignalsHeld(const SignalsHeld&) = delete;
  SignalsHeld& operator=(const SignalsHeld&) = delete;

 private:
  sigset_t previous_;
};

bool sameFile(const struct stat& a, const struct stat& b) {
  return a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

/// This host, as 8 hexadecimal digits of its name's digest.
std::string hostTag() {
  static const std::string tag = [] {
    char host[256] = "";
    ::gethostname(host, sizeof host - 1);
    return detail::hex(detail::digest(host)).substr(0, 8);
  }();
  return tag;
}

}  // namespace

namespace {

/// The parts of a temporary name `.<stem>.tmp.<host>-<pid>.<6 characters><ext>[.previous]`.
struct TemporaryName {
  std::string final_name, host;
  long pid = 0;
  bool previous = false;
};

std::optional<TemporaryName> parseTemporaryName(std::string name) {
  TemporaryName t;
  const std::string kPrevious = ".previous";
  if (name.size() > kPrevious.size() &&
      name.compare(name.size() - kPrevious.size(), kPrevious.size(), kPrevious) == 0) {
    t.previous = true;
    name.resize(name.size() - kPrevious.size());
  }
  const std::size_t tmp = name.rfind(".tmp.");
  if (name.size() < 2 || name[0] != '.' || tmp == std::string::npos || tmp < 2)
    return std::nullopt;
  const std::string stem = name.substr(1, tmp - 1);
  const std::string rest = name.substr(tmp + 5);  // <host>-<pid>.<6 characters><ext>
  const std::size_t dash = rest.find('-'),
                    dot = rest.find('.', dash == std::string::npos ? 0 : dash);
  if (dash != 8 || dot == std::string::npos || dot == dash + 1 || dot - dash - 1 > 9 ||
      rest.size() < dot + 7)
    return std::nullopt;
  t.host = rest.substr(0, 8);
  const std::string pid = rest.substr(dash + 1, dot - dash - 1);
  const std::string random = rest.substr(dot + 1, 6), ext = rest.substr(dot + 7);
  const auto all = [](const std::string& text, int (*is)(int)) {
    return std::all_of(text.begin(), text.end(),
                       [&](char c) { return is(static_cast<unsigned char>(c)) != 0; });
  };
  if (!all(t.host, ::isxdigit) || !all(pid, ::isdigit) || !all(random, ::isalnum) ||
      (!ext.empty() && (ext[0] != '.' || ext.find('.', 1) != std::string::npos)))
    return std::nullopt;
  t.pid = std::stol(pid);
  t.final_name = stem + ext;
  return t;
}

}  // namespace

std::vector<std::string> removeLeftovers(const std::string& dir, const std::string& input) {
  std::vector<std::string> done;
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    return done;
  std::vector<fs::path> names;
  for (const auto& e : fs::directory_iterator(dir, ec))
    names.push_back(e.path());
  std::sort(names.begin(), names.end());
  for (const fs::path& path : names) {
    const std::string name = path.filename().string();
    const std::optional<TemporaryName> m = parseTemporaryName(name);
    if (!m || m->host != hostTag())
      continue;
    const long pid = m->pid;
    if (pid == ::getpid() || ::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH)
      continue;  // its process is alive (or not ours to ask about)
    struct stat st = {};
    if (::lstat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode) || st.st_uid != ::getuid() ||
        (!input.empty() && fs::equivalent(path, input, ec)))
      continue;
    const fs::path final_path = path.parent_path() / m->final_name;
    struct stat there = {};
    if (m->previous && ::lstat(final_path.c_str(), &there) != 0) {
      if (::rename(path.c_str(), final_path.c_str()) == 0)
        done.push_back("put back " + final_path.filename().string() + " (kept aside as " + name +
                       ")");
      continue;
    }
    if (::unlink(path.c_str()) == 0)
      done.push_back("removed " + name);
  }
  return done;
}

OutputFiles::~OutputFiles() {
  for (const auto& p : pending_) {
    ::unlink(p.tmp.c_str());
    detail::releaseTemporary(p.slot);
  }
}

int OutputFiles::renameFile(const char* from, const char* to) {
  return ::rename(from, to);
}

void OutputFiles::add(const std::string& name,
                      const std::function<void(const std::string& path)>& write) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec || !fs::is_directory(dir_))
    throw RunError("output.dir '" + dir_ + "': cannot create the directory (" +
                   (ec ? detail::errnoText(ec.value()) : std::string("not a directory")) + ")");
  const fs::path final_path = fs::path(dir_) / name;
  for (const auto& p : pending_)
    if (p.final_path == final_path.string())
      throw RunError("output '" + final_path.string() +
                     "' would be written twice (two outputs have the same name); give each its "
                     "own name");
  for (const std::string& input : protected_)
    if (fs::equivalent(final_path, input, ec))
      throw RunError("output '" + final_path.string() + "' is the input '" + input +
                     "': nothing is written over it; choose another name or output.dir");

  // A fresh name created exclusively (O_EXCL: never an existing file, never through a symlink
  // planted there), in the output directory so that the final rename is atomic; the extension
  // stays last so that writers that look at it (PLY, OFF) still recognise the format.
  Pending pending;
  const int fd = detail::createTemporary(
      (fs::path(dir_) / ("." + final_path.stem().string() + ".tmp." + hostTag() + "-" +
                         std::to_string(::getpid()) + "."))
          .string(),
      final_path.extension().string(), pending.tmp, pending.slot);
  if (fd < 0)
    throw RunError("output '" + final_path.string() +
                   "': cannot create a file in output.dir: " + detail::errnoText(errno));
  pending.final_path = final_path.string();
  struct stat created = {};
  const bool stat_ok = ::fstat(fd, &created) == 0 && ::fchmod(fd, defaultFileMode()) == 0;
  ::close(fd);
  pending_.push_back(pending);
  if (!stat_ok)
    throw RunError("output '" + final_path.string() + "': " + detail::errnoText(errno));
  pending_.back().device = created.st_dev;
  pending_.back().inode = created.st_ino;
  try {
    write(pending.tmp);
  } catch (const RunError&) {
    throw;
  } catch (const std::exception& e) {
    throw RunError("output '" + final_path.string() + "': " + e.what());
  }
  checkStillOurs(pending_.back());
}

void OutputFiles::checkStillOurs(const Pending& p) const {
  struct stat now = {};
  if (::lstat(p.tmp.c_str(), &now) != 0)
    throw RunError("output '" + p.final_path + "': its temporary file '" + p.tmp + "' has gone (" +
                   detail::errnoText(errno) + ")");
  struct stat created = {};
  created.st_dev = static_cast<dev_t>(p.device);
  created.st_ino = static_cast<ino_t>(p.inode);
  if (!S_ISREG(now.st_mode) || !sameFile(now, created))
    throw RunError("output '" + p.final_path + "': its temporary file '" + p.tmp +
                   "' was replaced by another file while it was written; nothing is committed");
}

void OutputFiles::addText(const std::string& name, const std::string& text) {
  add(name, [&](const std::string& path) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out)
      throw RunError("cannot open '" + path + "': " + detail::errnoText(errno));
    out << text;
    out.close();
    if (!out)
      throw RunError("cannot write '" + path + "': " + detail::errnoText(errno));
  });
}

std::vector<std::string> OutputFiles::commit() {
  const SignalsHeld held;
  // Everything that can be checked is checked before the first rename.
  for (const auto& p : pending_) {
    checkStillOurs(p);
    std::error_code ec;
    if (fs::is_directory(fs::symlink_status(p.final_path, ec)))
      throw RunError("output '" + p.final_path + "' is a directory; nothing is committed");
  }
  // A file already at a final name is kept under a backup name (a hard link, else a rename)
  // until every rename has succeeded, so that a failure can put everything back.
  struct Step {
    std::string backup;  // empty: nothing was at the final name
    bool linked = false;
    bool renamed = false;
  };
  std::vector<Step> steps(pending_.size());
  auto rollBack = [&](const std::string& why) {
    for (std::size_t j = steps.size(); j-- > 0;) {
      const auto& p = pending_[j];
      if (steps[j].backup.empty()) {
        if (steps[j].renamed)
          ::unlink(p.final_path.c_str());
      } else if (steps[j].linked && !steps[j].renamed) {
        ::unlink(steps[j].backup.c_str());  // the final name still holds the old file
      } else {
        ::rename(steps[j].backup.c_str(), p.final_path.c_str());
      }
    }
    throw RunError(why + "; the earlier outputs were put back, nothing is committed");
  };
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    const auto& p = pending_[i];
    struct stat existing = {};
    if (::lstat(p.final_path.c_str(), &existing) == 0) {
      std::string backup = p.tmp + ".previous";
      if (::link(p.final_path.c_str(), backup.c_str()) == 0) {
        steps[i].linked = true;
      } else if (::rename(p.final_path.c_str(), backup.c_str()) != 0) {
        rollBack("output '" + p.final_path + "': cannot keep the file it replaces (" +
                 detail::errnoText(errno) + ")");
      }
      steps[i].backup = backup;
    }
    if (renameFile(p.tmp.c_str(), p.final_path.c_str()) != 0)
      rollBack("output '" + p.final_path + "': cannot rename into place (" +
               detail::errnoText(errno) + ")");
    steps[i].renamed = true;
  }
  if (announce_commit_)
    detail::noteOutputsCommitted();
  std::vector<std::string> written;
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    if (!steps[i].backup.empty())
      ::unlink(steps[i].backup.c_str());
    detail::releaseTemporary(pending_[i].slot);
    written.push_back(pending_[i].final_path);
  }
  pending_.clear();
  return written;
}

}  // namespace slipfit::pipeline
