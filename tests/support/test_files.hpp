// Files Loom's own tests read and write: the course data beside the
// repository, and a fresh temporary folder per test. Graphs run in-process
// through loom::testing (loom/testing.hpp); these stay here because they
// name this checkout's data folder and GoogleTest's current test, which the
// installed kit, free of any test framework and of this tree, cannot know.
#pragma once

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace loom::test {

// ../shared/data/<relative>, or an empty path when the data is absent.
std::filesystem::path data_file(const std::string& relative);
// Skips the current test when the data file is absent.
#define LOOM_REQUIRE_DATA(path_var, relative)                               \
  const std::filesystem::path path_var = ::loom::test::data_file(relative); \
  if (path_var.empty()) GTEST_SKIP() << "course data absent: " << (relative)

// A fresh, empty temporary folder named after the current test.
std::filesystem::path temp_dir();

// The bytes of `file` as a string (empty when it cannot be read).
std::string read_text(const std::filesystem::path& file);

}  // namespace loom::test
