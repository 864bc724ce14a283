#include "video_files.hpp"

#include "io_library.hpp"

namespace loom::io {

const VideoFiles& video_files() {
  // A throwing initializer leaves it uninitialized: the next call tries again.
  static const auto* table =
      static_cast<const VideoFiles*>(open_io_library("libloom_video_files.so", "loom_video_files", kVideoFilesVersion, "write videos"));
  return *table;
}

}  // namespace loom::io
