// Starting and waiting for the processes of a farm job (tasks, sbatch).
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace loom::runner {

// Starts argv[0] (a path) with stdout and stderr going to `log_fd` (-1:
// inherited; opened by the caller, so that no link is followed), in a
// process group of its own when `own_group` (so that signalling the group
// reaches the task and its `loom run`, as scancel does). Returns -1 with
// errno set when it cannot start.
pid_t spawn_process(const std::vector<std::string>& argv, int log_fd, bool own_group);

// The exit code of `pid`, or 128 + the signal that killed it (*signalled set).
// Returns -1 with errno EINTR when a signal arrives first.
int wait_process(pid_t pid, bool* signalled);

// The path of this process's executable (/proc/self/exe), or "" when unknown.
std::string own_executable();

// Runs argv and returns its standard output (the exit code in *exit).
std::string capture_output(const std::vector<std::string>& argv, int* exit);

}  // namespace loom::runner
