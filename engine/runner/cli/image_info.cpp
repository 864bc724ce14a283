#include "cli/image_info.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "cli/run_settings.hpp"

namespace loom::runner {

std::filesystem::path image_files_library() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return exe.parent_path().parent_path() / "lib" / "libloom_image_files.so";
}

int image_info(const std::vector<std::string>& files) {
  const std::filesystem::path library = image_files_library();
  void* handle = ::dlopen(library.c_str(), RTLD_NOW | RTLD_LOCAL);
  using Entry = char* (*)(const char*, int*);
  auto entry = handle ? reinterpret_cast<Entry>(::dlsym(handle, "loom_image_info")) : nullptr;
  if (!entry) {
    std::cerr << "error: cannot load " << library.string() << ": "
              << (handle ? "no loom_image_info in it" : ::dlerror()) << "\n";
    return kPluginError;
  }
  int exit = kOk;
  for (const std::string& file : files) {
    int ok = 0;
    char* text = entry(file.c_str(), &ok);
    (ok ? std::cout : std::cerr) << (ok ? "" : "error: ") << (text ? text : "out of memory") << (ok ? "" : "\n");
    std::free(text);
    if (!ok) exit = kInvalid;
  }
  return exit;
}

}  // namespace loom::runner
