#include "interrupt.hpp"

#include <csignal>
#include <cstdlib>

namespace loom::runner {

namespace {
std::atomic<bool> g_interrupted{false};
extern "C" void on_sweep_or_task_interrupt(int) {
  if (g_interrupted.exchange(true)) std::_Exit(130);
}
}  // namespace

std::atomic<bool>& interrupt_flag() { return g_interrupted; }

// Without SA_RESTART, so that a process waiting for its children (waitpid)
// wakes up to pass the signal on.
void catch_interrupts() {
  struct sigaction action {};
  action.sa_handler = on_sweep_or_task_interrupt;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

}  // namespace loom::runner
