#include "io_library.hpp"

#include <filesystem>

#include <dlfcn.h>

#include "loom/error.hpp"
#include "loom/image.hpp"

namespace loom::io {

const void* open_io_library(const std::string& file, const char* entry, int version, const std::string& purpose) {
  Dl_info info{};
  if (::dladdr(reinterpret_cast<void*>(&loom::with_encoding), &info) == 0 || !info.dli_fname)
    throw Error("cannot " + purpose + ": cannot find the folder of libloom_types.so to load " + file + " from");
  const std::filesystem::path path = std::filesystem::path(info.dli_fname).parent_path() / file;
  void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) throw Error("cannot " + purpose + ": " + std::string(::dlerror()));
  using Entry = const void* (*)();
  auto function = reinterpret_cast<Entry>(::dlsym(handle, entry));
  const void* table = function ? function() : nullptr;
  if (!table || *static_cast<const int*>(table) != version)
    throw Error("cannot " + purpose + ": " + path.string() + " is not the one of this build of Loom (rebuild Loom)");
  return table;
}

}  // namespace loom::io
