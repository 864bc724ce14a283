#include "video_files.hpp"

#include "io_library.hpp"

namespace loom::io {

const VideoFiles& video_files() {
  return io_library<VideoFiles>("libloom_video_files.so", "loom_video_files", kVideoFilesVersion, "write videos");
}

}  // namespace loom::io
