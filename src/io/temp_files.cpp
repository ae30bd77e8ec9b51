#include "temp_files.hpp"

#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <mutex>

#include "camopt/core/error.hpp"

namespace camopt::io::detail {
namespace {

// a fixed table the handler reads without allocating: a run holds a handful of temp files
constexpr std::size_t kSlots = 64;
constexpr std::size_t kPathBytes = 4096;  // PATH_MAX, with the terminating zero

struct Slot {
  std::atomic<bool> armed{false};  // read by the handler: path holds a whole temp name
  bool taken = false;              // guarded by slot_mutex
  char path[kPathBytes] = {};
};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler reads Slot::armed");

Slot slots[kSlots];
std::mutex slot_mutex;
constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT};

// async-signal-safe: unlink every armed temp file, then die of the same signal
extern "C" void remove_temps_and_reraise(int signal_number) {
  for (Slot& slot : slots)
    if (slot.armed.load(std::memory_order_acquire)) ::unlink(slot.path);
  ::signal(signal_number, SIG_DFL);
  ::raise(signal_number);  // pending until the handler returns (the signal is blocked in it)
}

void install_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (const int signal_number : kSignals) {
      struct sigaction previous {};
      if (::sigaction(signal_number, nullptr, &previous) != 0) continue;
      if (!(previous.sa_flags & SA_SIGINFO) && previous.sa_handler == SIG_IGN) continue;
      struct sigaction action {};
      action.sa_handler = remove_temps_and_reraise;
      ::sigfillset(&action.sa_mask);  // no other caught signal interrupts the cleanup
      ::sigaction(signal_number, &action, nullptr);
    }
  });
}

Slot& take_slot() {
  const std::lock_guard<std::mutex> lock(slot_mutex);
  for (Slot& slot : slots)
    if (!slot.taken) {
      slot.taken = true;
      return slot;
    }
  CAMOPT_ASSERT_MSG(false, "temp_files: more than 64 temporary output files at once");
  return slots[0];
}

void release_slot(Slot& slot) {
  slot.armed.store(false, std::memory_order_release);
  const std::lock_guard<std::mutex> lock(slot_mutex);
  slot.taken = false;
}

}  // namespace

int create_registered_temp(const std::string& path, std::string& temp_path) {
  install_handlers();
  const std::string pattern = path + ".tmp-XXXXXX";
  if (pattern.size() >= kPathBytes) {
    errno = ENAMETOOLONG;
    return -1;
  }
  // armed before mkstemp creates the file, so no signal can fall between the two; mkstemp
  // only replaces the X's, so the handler always sees a whole temp name
  Slot& slot = take_slot();
  std::memcpy(slot.path, pattern.c_str(), pattern.size() + 1);
  slot.armed.store(true, std::memory_order_release);
  const int fd = ::mkstemp(slot.path);
  const int error = errno;
  temp_path = slot.path;
  if (fd < 0) release_slot(slot);
  errno = error;
  return fd;
}

void forget_temp(const std::string& temp_path) {
  const std::lock_guard<std::mutex> lock(slot_mutex);
  for (Slot& slot : slots)
    if (slot.taken && temp_path == slot.path) {
      slot.armed.store(false, std::memory_order_release);
      slot.taken = false;
      return;
    }
}

}  // namespace camopt::io::detail
