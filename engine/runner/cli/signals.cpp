#include "cli/signals.hpp"

#include <csignal>
#include <cstring>

#include <unistd.h>

#include "loom/temporary_file.hpp"

namespace loom::runner {
namespace {

constexpr int kInterrupted = 130;
std::atomic<bool> g_cancel{false};
std::atomic<int> g_signal{0};  // lock-free: set from the handler
bool g_leave_after_grace = true;

void say(const char* text) {
  const ssize_t ignored = ::write(STDERR_FILENO, text, std::strlen(text));
  (void)ignored;
}

// Only async-signal-safe calls below: unlink (inside remove_temporary_files),
// write, alarm, raise, _exit.
extern "C" void leave_now(int) {
  loom::remove_temporary_files();
  _exit(kInterrupted);
}

extern "C" void on_alarm(int) {
  say("loom: the run did not stop within 5 s of the signal: leaving without it\n");
  leave_now(SIGALRM);
}

extern "C" void on_stop_signal(int signal) {
  int none = 0;
  g_signal.compare_exchange_strong(none, signal);
  if (g_cancel.exchange(true)) {  // the second signal: leave now, saying so
    say("loom: a second stop signal: leaving now\n");
    leave_now(0);
  }
  if (g_leave_after_grace) ::alarm(kGraceSeconds);
}

// A crash (or an abort from an uncaught exception) still removes the staging
// files, then dies of the same signal, so the crash is reported as one.
extern "C" void on_fatal_signal(int signal) {
  loom::remove_temporary_files();
  ::raise(signal);  // the handler was reset to the default on entry
}

void handle(int signal, void (*handler)(int), int flags = 0) {
  struct sigaction action {};
  action.sa_handler = handler;
  action.sa_flags = flags;
  sigemptyset(&action.sa_mask);
  ::sigaction(signal, &action, nullptr);
}

}  // namespace

std::atomic<bool>& cancel_flag() { return g_cancel; }

std::string interrupted_message() {
  const std::string name = stop_signal_name();
  return "error: interrupted" + (name.empty() ? std::string() : " by " + name) +
         ": the nodes still running were cancelled and wrote no files (a sink that gathers every frame, such as "
         "SaveVideo, writes nothing unless it ends)";
}

const char* stop_signal_name() {
  switch (g_signal.load()) {
    case SIGINT: return "SIGINT (Ctrl-C)";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    case SIGPIPE: return "SIGPIPE (the reader of the output went away)";
    default: return "";
  }
}

void stop_on_signals(bool leave_after_grace) {
  g_leave_after_grace = leave_after_grace;
  for (int s : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) handle(s, on_stop_signal);
  handle(SIGALRM, on_alarm);
  handle(SIGXFSZ, SIG_IGN);
  for (int s : {SIGSEGV, SIGBUS, SIGABRT, SIGFPE, SIGILL}) handle(s, on_fatal_signal, SA_RESETHAND | SA_NODEFER);
}

}  // namespace loom::runner
