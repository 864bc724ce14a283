// How `loom run` ends when told to stop. SIGINT, SIGTERM, SIGHUP and SIGPIPE
// (the reader of its output went away) set the cancel flag: nodes stop at
// their next check and the run ends with exit 130. A second such signal, or
// kGraceSeconds without the run ending (a node blocked in a system call or a
// library that never checks), removes this process's staging files and exits
// 130 at once. SIGXFSZ is ignored, so a file-size limit makes a write fail
// with an error instead of killing the process mid-file. A crash (SIGSEGV,
// SIGBUS, SIGABRT, SIGFPE, SIGILL) removes the staging files before the
// process dies of it.
#pragma once

#include <atomic>
#include <string>

namespace loom::runner {

constexpr unsigned kGraceSeconds = 5;

// The process's cancel flag, which the signals set: `loom run`, sweeps and
// the dispatcher all stop on it.
std::atomic<bool>& cancel_flag();

// Installs the handlers. A process that waits for children it has passed the
// signal on to (the local dispatcher) has no grace timeout: it waits for them
// to end (a second signal still leaves at once). The handlers do not restart
// interrupted calls, so a wait for children wakes up to pass the signal on.
void stop_on_signals(bool leave_after_grace = true);

// The first stop signal received ("SIGTERM"), or "" when none was: the run's
// last line names it, since a cancelled sink writes nothing of its own.
const char* stop_signal_name();
// "error: interrupted by SIGTERM: ...", the last line of a cancelled run.
std::string interrupted_message();

}  // namespace loom::runner
