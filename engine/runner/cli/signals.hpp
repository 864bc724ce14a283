// How `loom run` ends when told to stop. SIGINT, SIGTERM, SIGHUP and SIGPIPE
// (the reader of its output went away) set the cancel flag: nodes stop at
// their next check and the run ends with exit 130. A second such signal, or
// the grace without the run ending (a node inside a library call that never
// checks, such as a sparse factorization or a driver's shader compile),
// removes this process's staging files and exits 130 at once. SIGXFSZ is
// ignored, so a file-size limit makes a write fail with an error instead of
// killing the process mid-file. A crash (SIGSEGV, SIGBUS, SIGABRT, SIGFPE,
// SIGILL) removes the staging files before the process dies of it.
#pragma once

#include <atomic>
#include <string>

namespace loom::runner {

// How long a stop signal waits for the run to end on its own.
enum class Grace {
  brief,  // kBriefGraceMs: a run whose nodes stop at their next check, so that
          // Ctrl-C is answered at once even inside a call that cannot stop
  ranks,  // kRanksGraceMs: an MPI rank, whose peers must end with it (MPI_Abort)
  none    // a process that waits for its children, or for a change (--watch)
};
constexpr int kBriefGraceMs = 300;
constexpr int kRanksGraceMs = 5000;
// LOOM_STOP_GRACE (seconds) overrides either: a test that checks a node stops
// at its own checks sets it long, so the grace cannot hide one that never does.

// The process's cancel flag, which the signals set: `loom run`, sweeps and
// the dispatcher all stop on it.
std::atomic<bool>& cancel_flag();

// Installs the handlers. A process that waits for children it has passed the
// signal on to (the local dispatcher) has no grace: it waits for them to end
// (a second signal still leaves at once). The handlers do not restart
// interrupted calls, so a wait for children wakes up to pass the signal on.
void stop_on_signals(Grace grace);
// The nodes have returned: a grace timer a signal armed is stopped, so that
// the run's own ending (its last line, the cache trim) is not cut short by it.
// A later signal arms it again.
void nodes_returned();

// "error: interrupted by SIGTERM: ...", the last line of a cancelled run.
std::string interrupted_message();

}  // namespace loom::runner
