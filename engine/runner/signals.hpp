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

namespace loom::runner {

constexpr unsigned kGraceSeconds = 5;

void stop_on_signals(std::atomic<bool>& cancel);

}  // namespace loom::runner
