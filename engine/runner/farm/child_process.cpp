#include "farm/child_process.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <iostream>

extern char** environ;

namespace loom::runner {

namespace {
std::vector<char*> c_argv(const std::vector<std::string>& argv) {
  std::vector<char*> v;
  for (const auto& a : argv) v.push_back(const_cast<char*>(a.c_str()));
  v.push_back(nullptr);
  return v;
}

LoomMain g_loom_main = nullptr;
bool g_fork_runs = false;

// A forked child's end: what it printed is flushed, then it exits without
// running the static destructors of the parent's libraries a second time.
[[noreturn]] void leave_child(int exit) {
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  ::_exit(exit);
}

}  // namespace

void set_loom_main(LoomMain main) { g_loom_main = main; }

void fork_loom_runs(bool on) { g_fork_runs = on; }

pid_t fork_call(const std::function<int()>& call, bool own_group) {
  std::cout.flush();  // else the child would print the parent's buffered text again
  std::cerr.flush();
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  if (own_group) ::setpgid(0, 0);
  int exit = 1;
  try {
    exit = call();
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
  }
  leave_child(exit);
}

pid_t start_loom(const std::vector<std::string>& argv, int log_fd, bool own_group) {
  if (!g_fork_runs || !g_loom_main || argv.empty() || argv[0] != own_executable())
    return spawn_process(argv, log_fd, own_group);
  return fork_call(
      [&] {
        if (log_fd >= 0) {
          ::dup2(log_fd, 1);
          ::dup2(log_fd, 2);
          ::close(log_fd);
        }
        auto args = c_argv(argv);
        return g_loom_main(static_cast<int>(argv.size()), args.data());
      },
      own_group);
}

pid_t spawn_process(const std::vector<std::string>& argv, int log_fd, bool own_group) {
  posix_spawn_file_actions_t files;
  posix_spawnattr_t attr;
  posix_spawn_file_actions_init(&files);
  posix_spawnattr_init(&attr);
  if (log_fd >= 0) {
    posix_spawn_file_actions_adddup2(&files, log_fd, 1);
    posix_spawn_file_actions_adddup2(&files, log_fd, 2);
  }
  if (own_group) {
    posix_spawnattr_setpgroup(&attr, 0);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
  }
  pid_t pid = -1;
  auto args = c_argv(argv);
  if (const int error = posix_spawn(&pid, args[0], &files, &attr, args.data(), environ); error != 0) {
    pid = -1;
    errno = error;
  }
  const int error = errno;
  posix_spawn_file_actions_destroy(&files);
  posix_spawnattr_destroy(&attr);
  errno = error;
  return pid;
}

int wait_process(pid_t pid, bool* signalled) {
  int status = 0;
  if (::waitpid(pid, &status, 0) != pid) return -1;
  *signalled = WIFSIGNALED(status);
  return *signalled ? 128 + WTERMSIG(status) : WEXITSTATUS(status);
}

std::string own_executable() {
  std::error_code ec;
  const std::filesystem::path p = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : p.string();
}

std::string capture_output(const std::vector<std::string>& argv, int* exit) {
  int fds[2];
  *exit = -1;
  if (::pipe(fds) != 0) return {};
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_adddup2(&files, fds[1], 1);
  posix_spawn_file_actions_addclose(&files, fds[0]);
  pid_t pid = -1;
  auto args = c_argv(argv);
  const bool started = posix_spawnp(&pid, args[0], &files, nullptr, args.data(), environ) == 0;
  posix_spawn_file_actions_destroy(&files);
  ::close(fds[1]);
  std::string out;
  char buffer[4096];
  for (ssize_t n; (n = ::read(fds[0], buffer, sizeof buffer)) != 0;) {
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) break;
    out.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  bool signalled = false;
  if (started)
    while ((*exit = wait_process(pid, &signalled)) == -1 && errno == EINTR) {
    }
  return out;
}

}  // namespace loom::runner
