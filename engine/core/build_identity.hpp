// The identity of a built library by its content, for the persistent cache's
// keys: two machines with the same build share entries whatever the install
// path or file times.
#pragma once

#include <cstdint>
#include <filesystem>

namespace loom::detail {

// The library's GNU build ID (a hash of its linked contents that the linker
// writes into an ELF note; Debian's GCC links one in by default), hashed to 64
// bits; without one, a hash of the file's bytes. Remembered per path, size and
// modification time, so each library is read once per process. 0 when the
// file cannot be read.
std::uint64_t build_identity(const std::filesystem::path& library);

}  // namespace loom::detail
