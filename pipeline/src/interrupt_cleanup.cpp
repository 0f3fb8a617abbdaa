#include "interrupt_cleanup.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <random>

namespace slipfit::pipeline::detail {

namespace {

// The handler may only call async-signal-safe functions (unlink, write, _exit) and read
// lock-free atomics: the paths live in fixed buffers, a slot is published once its path is
// complete.
constexpr int kSlots = 256;
constexpr std::size_t kPathBytes = 4096;
enum SlotState : int { kFree = 0, kWriting = 1, kReady = 2 };

std::atomic<int> g_state[kSlots];
char g_path[kSlots][kPathBytes];
std::atomic<bool> g_installed{false};
std::atomic<bool> g_committed{false};

extern "C" void onInterrupt(int signal_number) {
  for (int i = 0; i < kSlots; ++i)
    if (g_state[i].load(std::memory_order_acquire) == kReady)
      ::unlink(g_path[i]);
  const bool committed = g_committed.load(std::memory_order_acquire);
  const char* text =
      signal_number == SIGINT
          ? (committed ? "slipfit: error: interrupted (SIGINT) after the outputs were written\n"
                       : "slipfit: error: interrupted (SIGINT); no output was written\n")
          : (committed ? "slipfit: error: terminated (SIGTERM) after the outputs were written\n"
                       : "slipfit: error: terminated (SIGTERM); no output was written\n");
  [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, text, std::strlen(text));
  ::_exit(128 + signal_number);
}

}  // namespace

void installInterruptCleanup() {
  if (g_installed.exchange(true))
    return;
  struct sigaction action = {};
  action.sa_handler = onInterrupt;
  sigemptyset(&action.sa_mask);
  sigaddset(&action.sa_mask, SIGINT);
  sigaddset(&action.sa_mask, SIGTERM);
  for (const int s : {SIGINT, SIGTERM}) {
    struct sigaction previous = {};
    // A shell starts background jobs with SIGINT ignored: that choice is kept.
    if (::sigaction(s, nullptr, &previous) == 0 && previous.sa_handler == SIG_IGN)
      continue;
    ::sigaction(s, &action, nullptr);
  }
}

int registerTemporary(const std::string& path) {
  if (path.size() + 1 > kPathBytes)
    return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = kFree;
    if (g_state[i].compare_exchange_strong(expected, kWriting, std::memory_order_acq_rel)) {
      std::memcpy(g_path[i], path.c_str(), path.size() + 1);
      g_state[i].store(kReady, std::memory_order_release);
      return i;
    }
  }
  return -1;
}

int createTemporary(const std::string& prefix, const std::string& suffix, std::string& path,
                    int& slot) {
  static constexpr char kLetters[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
  static thread_local std::mt19937_64 random(std::random_device{}());
  std::uniform_int_distribution<std::size_t> pick(0, sizeof kLetters - 2);
  for (int attempt = 0; attempt < 100; ++attempt) {
    path = prefix;
    for (int i = 0; i < 6; ++i)
      path += kLetters[pick(random)];
    path += suffix;
    // Registered first: a signal from here on unlinks the path, which is harmless before the
    // file exists (and the process then exits before creating it).
    slot = registerTemporary(path);
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd >= 0)
      return fd;
    const int error = errno;
    releaseTemporary(slot);
    slot = -1;
    if (error != EEXIST) {
      errno = error;
      return -1;
    }
  }
  errno = EEXIST;
  return -1;
}

void noteOutputsCommitted() {
  g_committed.store(true, std::memory_order_release);
}

void releaseTemporary(int slot) {
  if (slot >= 0 && slot < kSlots)
    g_state[slot].store(kFree, std::memory_order_release);
}

}  // namespace slipfit::pipeline::detail
