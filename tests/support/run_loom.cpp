#include "run_loom.hpp"

#include <array>
#include <cstdio>

#include <sys/wait.h>

#include "test_files.hpp"

namespace loom::test {

std::string fresh_cache_env(const std::string& arguments) {
  if (arguments.find("--cache") != std::string::npos) return "";
  return "XDG_CACHE_HOME=" + (temp_dir() / "xdg-cache").string() + " ";
}

int run_loom(const std::string& arguments, std::string* output) { return run_loom_env("", arguments, output); }

int run_loom_env(const std::string& environment, const std::string& arguments, std::string* output) {
  return run_shell("env " + environment + " " + fresh_cache_env(arguments) + LOOM_RUNNER + " " + arguments, output);
}

int run_shell(const std::string& script, std::string* output) {
  std::string cmd = "( " + script + " ) 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return -1;
  std::string text;
  std::array<char, 4096> buffer{};
  std::size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) text.append(buffer.data(), n);
  int status = ::pclose(pipe);
  if (output) *output = text;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace loom::test
