// The built `loom` command and shell scripts, run as a user runs them: exit
// code and everything printed. For tests of the runner's own behaviour; a
// graph's results are checked in-process with loom::testing instead.
#pragma once

#include <string>

namespace loom::test {

// Runs the built `loom` command; returns its exit code, stdout+stderr in *output.
// Unless the arguments name a --cache folder, the run gets a fresh, empty
// persistent cache (XDG_CACHE_HOME in a new temporary folder).
int run_loom(const std::string& arguments, std::string* output = nullptr);
// run_loom with VAR=value assignments in front of the command.
int run_loom_env(const std::string& environment, const std::string& arguments, std::string* output = nullptr);
// Runs a shell script; returns its exit code, stdout+stderr in *output.
int run_shell(const std::string& script, std::string* output = nullptr);
// The environment assignment run_loom puts in front of the command.
std::string fresh_cache_env(const std::string& arguments);

}  // namespace loom::test
