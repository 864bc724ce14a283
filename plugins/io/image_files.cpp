#include "image_files.hpp"

#include <dlfcn.h>

#include "loom/error.hpp"
#include "loom/image.hpp"

namespace loom::io {

namespace {

// lib/ of the build or the install: the folder of libloom_types.so, which
// every user of these codecs (the io plugin, its tests) links.
std::filesystem::path library_path() {
  Dl_info info{};
  if (::dladdr(reinterpret_cast<void*>(&loom::with_encoding), &info) == 0 || !info.dli_fname)
    throw Error("cannot find the folder of libloom_types.so to load libloom_image_files.so from");
  return std::filesystem::path(info.dli_fname).parent_path() / "libloom_image_files.so";
}

const ImageFiles* load() {
  const std::filesystem::path path = library_path();
  void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) throw Error("cannot read or write image files: " + std::string(::dlerror()));
  using Entry = const ImageFiles* (*)();
  auto entry = reinterpret_cast<Entry>(::dlsym(handle, "loom_image_files"));
  const ImageFiles* table = entry ? entry() : nullptr;
  if (!table || table->version != kImageFilesVersion)
    throw Error(path.string() + " is not the image library of this build of Loom (rebuild Loom)");
  return table;
}

}  // namespace

const ImageFiles& image_files() {
  // A throwing initializer leaves it uninitialized: the next call tries again.
  static const ImageFiles* table = load();
  return *table;
}

}  // namespace loom::io
