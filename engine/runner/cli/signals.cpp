#include "cli/signals.hpp"

#include <array>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include <sys/time.h>
#include <unistd.h>

#include "loom/temporary_file.hpp"

namespace loom::runner {
namespace {

constexpr int kInterrupted = 130;
std::atomic<bool> g_cancel{false};
std::atomic<int> g_signal{0};  // lock-free: set from the handler
std::atomic<int> g_grace_ms{kBriefGraceMs};  // 0: no grace timer; read by the handler
// What a leave after the grace prints, for each stop signal: written before
// the handlers are installed (a handler may not allocate), into fixed
// buffers, since --watch installs them again for every run.
constexpr std::array<int, 4> kStopSignals{SIGINT, SIGTERM, SIGHUP, SIGPIPE};
char g_leave_lines[kStopSignals.size()][512];

void say(const char* text) {
  const ssize_t ignored = ::write(STDERR_FILENO, text, std::strlen(text));
  (void)ignored;
}

std::string signal_name(int signal) {
  switch (signal) {
    case SIGINT:
      return "SIGINT (Ctrl-C)";
    case SIGTERM:
      return "SIGTERM";
    case SIGHUP:
      return "SIGHUP";
    case SIGPIPE:
      return "SIGPIPE (the reader of the output went away)";
    default:
      return "";
  }
}

std::string message_for(int signal) {
  const std::string name = signal_name(signal);
  return "error: interrupted" + (name.empty() ? std::string() : " by " + name) +
         ": the nodes still running were cancelled and wrote no files (a sink that gathers every frame, such as "
         "SaveVideo, writes nothing unless it ends)";
}

// Only async-signal-safe calls below: unlink (inside remove_temporary_files),
// write, setitimer, raise, _exit.
extern "C" void leave_now(int) {
  loom::remove_temporary_files();
  _exit(kInterrupted);
}

extern "C" void on_alarm(int) {
  for (std::size_t i = 0; i < kStopSignals.size(); ++i)
    if (kStopSignals[i] == g_signal.load()) say(g_leave_lines[i]);
  leave_now(SIGALRM);
}

void start_grace_timer() {
  const int ms = g_grace_ms.load();
  itimerval timer{};
  timer.it_value.tv_sec = ms / 1000;
  timer.it_value.tv_usec = (ms % 1000) * 1000;
  ::setitimer(ITIMER_REAL, &timer, nullptr);  // a system call, safe in a handler on Linux
}

extern "C" void on_stop_signal(int signal) {
  int none = 0;
  g_signal.compare_exchange_strong(none, signal);
  if (g_cancel.exchange(true)) {  // the second signal: leave now, saying so
    say("loom: a second stop signal: leaving now\n");
    leave_now(0);
  }
  if (g_grace_ms > 0) start_grace_timer();
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

// The grace for `grace`, or LOOM_STOP_GRACE's when set.
int grace_ms(Grace grace) {
  const int ms = grace == Grace::brief ? kBriefGraceMs : grace == Grace::ranks ? kRanksGraceMs : 0;
  const char* text = std::getenv("LOOM_STOP_GRACE");
  if (!text || grace == Grace::none) return ms;
  char* end = nullptr;
  const double seconds = std::strtod(text, &end);
  if (end != text && *end == '\0' && seconds >= 0.01 && seconds <= 3600) return static_cast<int>(seconds * 1000);
  std::fprintf(stderr, "warning: LOOM_STOP_GRACE=%s is not a number of seconds from 0.01 to 3600: using %g\n", text,
               ms / 1000.0);
  return ms;
}

}  // namespace

std::atomic<bool>& cancel_flag() { return g_cancel; }

std::string interrupted_message() { return message_for(g_signal.load()); }

void nodes_returned() {
  itimerval off{};
  ::setitimer(ITIMER_REAL, &off, nullptr);
}

void stop_on_signals(Grace grace) {
  const int ms = grace_ms(grace);
  for (std::size_t i = 0; i < kStopSignals.size(); ++i)
    std::snprintf(g_leave_lines[i], sizeof g_leave_lines[i],
                  "loom: nodes still running %g s after the signal (inside a call that cannot stop, such as a "
                  "sparse factorization): leaving without them\n%s\n",
                  ms / 1000.0, message_for(kStopSignals[i]).c_str());
  g_grace_ms = ms;
  for (int s : kStopSignals) handle(s, on_stop_signal);
  handle(SIGALRM, on_alarm);
  handle(SIGXFSZ, SIG_IGN);
  for (int s : {SIGSEGV, SIGBUS, SIGABRT, SIGFPE, SIGILL}) handle(s, on_fatal_signal, SA_RESETHAND | SA_NODEFER);
}

}  // namespace loom::runner
