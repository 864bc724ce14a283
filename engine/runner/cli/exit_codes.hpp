// The exit codes of every `loom` command, named once: `loom --help` prints
// kExitCodesText, docs/architecture.md ("Exit codes") lists the same.
#pragma once

namespace loom::runner {

enum Exit {
  kOk = 0,
  kNodeFailed = 1,    // a node failed (other outputs still written); a farm task or sweep point failed
  kInvalid = 2,       // invalid graph, job folder or usage
  kPluginError = 3,   // a plugin could not be loaded
  kLaunchFailed = 4,  // a program the command starts could not be started or refused the work (sbatch, a task)
  kInterrupted = 130  // Ctrl-C (SIGINT) or SIGTERM: running nodes cancelled, no partial file left
};

inline constexpr const char* kExitCodesText =
    "Exit codes: 0 ok, 1 a node (or task, or sweep point) failed, 2 invalid graph or usage, "
    "3 plugin load error, 4 a program to start (sbatch, a task) failed to start or refused, 130 interrupted.";

}  // namespace loom::runner
