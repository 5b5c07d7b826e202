#include "fatal_signal.hpp"

#include <limits.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <mutex>

namespace sglab::runner {
namespace {

// Fixed tables, so the handler touches only async-signal-safe state: a slot is 0 (free), 1 (being
// filled) or 2 (holds a live temporary's path, or a child process group).
constexpr int kSlots = 256;
struct TempSlot {
  std::atomic<int> state{0};
  char path[PATH_MAX];
};
TempSlot g_temps[kSlots];
constexpr int kGroups = 16;
struct GroupSlot {
  std::atomic<int> state{0};
  pid_t group = 0;
};
GroupSlot g_groups[kGroups];
std::atomic<int> g_publishing{0};      // > 0 while an output set is being renamed
std::atomic<int> g_pending_signal{0};  // a signal that arrived meanwhile

void clean_up_and_die(int sig) {
  for (auto& slot : g_temps)
    if (slot.state.load() == 2) ::unlink(slot.path);
  for (auto& slot : g_groups)
    if (slot.state.load() == 2) {
      ::kill(-slot.group, SIGTERM);
      ::kill(-slot.group, SIGCONT);
    }
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

extern "C" void on_fatal_signal(int sig) {
  if (g_publishing.load() > 0) {  // finish publishing the set first; publish_end re-raises
    g_pending_signal.store(sig);
    return;
  }
  clean_up_and_die(sig);
}

void install_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (int sig : {SIGINT, SIGTERM}) {
      struct sigaction old {};
      if (::sigaction(sig, nullptr, &old) != 0 || old.sa_handler != SIG_DFL) continue;  // ignored or handled already
      struct sigaction sa {};
      sa.sa_handler = on_fatal_signal;
      sigemptyset(&sa.sa_mask);
      ::sigaction(sig, &sa, nullptr);
    }
  });
}

// The first free slot of `table`, marked 1 (being filled); -1 when every slot is taken.
template <class Slot, int N>
int claim(Slot (&table)[N]) {
  for (int i = 0; i < N; ++i) {
    int expected = 0;
    if (table[i].state.compare_exchange_strong(expected, 1)) return i;
  }
  return -1;
}

}  // namespace

int register_temporary(const std::string& path) {
  if (path.size() >= PATH_MAX) return -1;
  install_handlers();
  const int i = claim(g_temps);
  if (i < 0) return -1;
  std::memcpy(g_temps[i].path, path.c_str(), path.size() + 1);
  g_temps[i].state.store(2);
  return i;
}

void unregister_temporary(int slot) {
  if (slot >= 0) g_temps[slot].state.store(0);
}

void publish_begin() { g_publishing.fetch_add(1); }
void publish_end() {
  if (g_publishing.fetch_sub(1) == 1) {
    const int sig = g_pending_signal.exchange(0);
    if (sig != 0) clean_up_and_die(sig);
  }
}

int register_child_group(pid_t group) {
  if (group <= 0) return -1;
  install_handlers();
  const int i = claim(g_groups);
  if (i < 0) return -1;
  g_groups[i].group = group;
  g_groups[i].state.store(2);
  return i;
}

void unregister_child_group(int slot) {
  if (slot >= 0) g_groups[slot].state.store(0);
}

}  // namespace sglab::runner
