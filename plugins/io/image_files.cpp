#include "image_files.hpp"

#include "io_library.hpp"

namespace loom::io {

const ImageFiles& image_files() {
  // A throwing initializer leaves it uninitialized: the next call tries again.
  static const auto* table =
      static_cast<const ImageFiles*>(open_io_library("libloom_image_files.so", "loom_image_files", kImageFilesVersion, "read or write image files"));
  return *table;
}

}  // namespace loom::io
