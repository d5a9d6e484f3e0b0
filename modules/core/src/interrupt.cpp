#include "specht/core/interrupt.h"

#include <signal.h>

#include <atomic>
#include <csignal>

namespace specht {
namespace {

// Lock-free, so the handler may touch it (async-signal-safe).
std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free);

extern "C" void OnInterrupt(int sig) {
  int expected = 0;
  if (!g_signal.compare_exchange_strong(expected, sig)) {
    // The second signal: the default action now (terminate), as without a handler.
    std::signal(sig, SIG_DFL);
    std::raise(sig);
  }
}

}  // namespace

void InstallInterruptHandlers() {
  struct sigaction action {};
  action.sa_handler = OnInterrupt;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // reads and writes in flight carry on; loops poll the flag
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

bool InterruptRequested() { return g_signal.load(std::memory_order_relaxed) != 0; }

int InterruptSignal() { return g_signal.load(); }

std::string InterruptName() {
  const int sig = InterruptSignal();
  if (sig == 0) return "";
  if (sig == SIGINT) return "SIGINT";
  if (sig == SIGTERM) return "SIGTERM";
  return "signal " + std::to_string(sig);
}

int InterruptExitCode() {
  const int sig = InterruptSignal();
  return sig == 0 ? 0 : 128 + sig;
}

void ThrowIfInterrupted(const std::string& what) {
  if (InterruptRequested()) throw Interrupted(what + ": interrupted by " + InterruptName());
}

void RequestInterrupt(int signal) {
  int expected = 0;
  g_signal.compare_exchange_strong(expected, signal);
}

void ClearInterruptForTesting() { g_signal = 0; }

}  // namespace specht
