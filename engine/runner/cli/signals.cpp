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
int g_grace_ms = kBriefGraceMs;  // 0: no grace timer
// What a leave after the grace prints, made before any signal can arrive (a
// handler may not allocate): for each stop signal, its last line.
constexpr std::array<int, 4> kStopSignals{SIGINT, SIGTERM, SIGHUP, SIGPIPE};
std::array<std::string, kStopSignals.size()> g_leave_lines;

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
    if (kStopSignals[i] == g_signal.load()) say(g_leave_lines[i].c_str());
  leave_now(SIGALRM);
}

void start_grace_timer() {
  itimerval timer{};
  timer.it_value.tv_sec = g_grace_ms / 1000;
  timer.it_value.tv_usec = (g_grace_ms % 1000) * 1000;
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

}  // namespace

std::atomic<bool>& cancel_flag() { return g_cancel; }

std::string interrupted_message() { return message_for(g_signal.load()); }

void stop_on_signals(Grace grace) {
  g_grace_ms = grace == Grace::brief ? kBriefGraceMs : grace == Grace::ranks ? kRanksGraceMs : 0;
  if (const char* text = std::getenv("LOOM_STOP_GRACE"); text && grace != Grace::none) {
    char* end = nullptr;
    const double seconds = std::strtod(text, &end);
    if (end != text && *end == '\0' && seconds >= 0.01 && seconds <= 3600)
      g_grace_ms = static_cast<int>(seconds * 1000);
    else
      std::fprintf(stderr, "warning: LOOM_STOP_GRACE=%s is not a number of seconds from 0.01 to 3600: using %g\n", text,
                   g_grace_ms / 1000.0);
  }
  for (std::size_t i = 0; i < kStopSignals.size(); ++i) {
    const double seconds = g_grace_ms / 1000.0;
    char figure[32];
    std::snprintf(figure, sizeof figure, "%g", seconds);
    g_leave_lines[i] = std::string("loom: nodes still running ") + figure +
                       " s after the signal (inside a call that cannot stop, such as a sparse factorization): "
                       "leaving without them\n" +
                       message_for(kStopSignals[i]) + "\n";
  }
  for (int s : kStopSignals) handle(s, on_stop_signal);
  handle(SIGALRM, on_alarm);
  handle(SIGXFSZ, SIG_IGN);
  for (int s : {SIGSEGV, SIGBUS, SIGABRT, SIGFPE, SIGILL}) handle(s, on_fatal_signal, SA_RESETHAND | SA_NODEFER);
}

}  // namespace loom::runner
