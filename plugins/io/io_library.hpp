// The io plugin's libraries of its own (lib/libloom_image_files.so,
// lib/libloom_video_files.so): each holds one heavy dependency, opened at its
// first use rather than when the plugin loads (image_files.hpp, video_files.hpp
// say what each costs).
#pragma once

#include <string>

namespace loom::io {

// Opens `file` from lib/ of the build or the install (the folder of
// libloom_types.so, which every user of the codecs links) and returns the
// table its entry point returns, which begins with an int `version` that must
// equal the plugin's own (they are built together); throws loom::Error saying
// that `purpose` cannot be done and why. Never closed: the table lives as long
// as the process.
const void* open_io_library(const std::string& file, const char* entry, int version, const std::string& purpose);

// The table of `file`, opened at the first call (one that throws leaves it
// unopened: the next call tries again).
template <class Table>
const Table& io_library(const std::string& file, const char* entry, int version, const std::string& purpose) {
  static const auto* table = static_cast<const Table*>(open_io_library(file, entry, version, purpose));
  return *table;
}

}  // namespace loom::io
