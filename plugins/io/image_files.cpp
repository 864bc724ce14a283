#include "image_files.hpp"

#include "io_library.hpp"

namespace loom::io {

const ImageFiles& image_files() {
  return io_library<ImageFiles>("libloom_image_files.so", "loom_image_files", kImageFilesVersion,
                                "read or write image files");
}

}  // namespace loom::io
