// Starting and waiting for the processes of a farm job (tasks, sbatch).
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace loom::runner {

// Starts argv[0] (a path) with stdout and stderr going to `log_fd` (-1:
// inherited; opened by the caller, so that no link is followed), in a
// process group of its own when `own_group` (so that signalling the group
// reaches the task and its `loom run`, as scancel does). Returns -1 with
// errno set when it cannot start.
pid_t spawn_process(const std::vector<std::string>& argv, int log_fd, bool own_group);

// The `loom` command line as a function, registered by main.cpp, so that a
// process already holding the libraries a task needs can run the task's
// `loom run` in a forked child instead of starting `loom` again.
using LoomMain = int (*)(int argc, char** argv);
void set_loom_main(LoomMain main);

// Whether start_loom forks (the local dispatcher turns it on once it has
// loaded what the job's tasks need); off, every `loom` is started anew.
void fork_loom_runs(bool on);

// As spawn_process, but when forks are on, argv[0] is this process's own
// executable and the command line was registered, the child is a fork of
// this process that runs it without exec: it keeps every library already
// loaded here (the dynamic linking is most of what a small task costs:
// docs/farm.md, "What a task costs"). The same `loom` code runs on the same
// arguments; only /proc/PID/cmdline still shows the forking process's.
pid_t start_loom(const std::vector<std::string>& argv, int log_fd, bool own_group);

// Runs `call` in a forked child (in a process group of its own when asked),
// which exits with what it returns. Returns -1 with errno set when it cannot.
pid_t fork_call(const std::function<int()>& call, bool own_group);

// The exit code of `pid`, or 128 + the signal that killed it (*signalled set).
// Returns -1 with errno EINTR when a signal arrives first.
int wait_process(pid_t pid, bool* signalled);

// The path of this process's executable (/proc/self/exe), or "" when unknown.
std::string own_executable();

// Runs argv and returns its standard output (the exit code in *exit).
std::string capture_output(const std::vector<std::string>& argv, int* exit);

}  // namespace loom::runner
