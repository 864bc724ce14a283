// The entry points of lib/libloom_image_files.so: the table the io plugin
// reads and writes images through, and the text `loom info` prints (a C
// function, since the runner includes no plugin header).
#include <cstdlib>
#include <cstring>

#include <OpenImageIO/imageio.h>

#include "loom/error.hpp"
#include "oiio_module.hpp"

namespace {

// OpenImageIO's own thread pools (and OpenEXR's) would run beside the TBB
// arena that `--threads` bounds; Loom's parallelism is TBB's (decision 16's
// rule for BLAS). Files are small beside the nodes that make them.
const bool kSingleThreaded = [] {
  OIIO::attribute("threads", 1);
  OIIO::attribute("exr_threads", -1);  // -1: no OpenEXR thread pool at all
  return true;
}();

const loom::io::ImageFiles kTable = {loom::io::kImageFilesVersion, &loom::io::oiio::read, &loom::io::oiio::write};

}  // namespace

extern "C" __attribute__((visibility("default"))) const loom::io::ImageFiles* loom_image_files() {
  (void)kSingleThreaded;
  return &kTable;
}

// Text for `loom info PATH` in a malloc'ed string the caller frees; *ok is 0
// when it is an error message instead.
extern "C" __attribute__((visibility("default"))) char* loom_image_info(const char* path, int* ok) {
  (void)kSingleThreaded;
  std::string text;
  try {
    text = loom::io::oiio::describe(path);
    *ok = 1;
  } catch (const std::exception& e) {
    text = e.what();
    *ok = 0;
  }
  char* copy = static_cast<char*>(std::malloc(text.size() + 1));
  if (copy) std::memcpy(copy, text.c_str(), text.size() + 1);
  return copy;
}
