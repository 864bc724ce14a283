// A file a reader is about to open must be a regular file: open() on a FIFO
// blocks until a writer appears (forever), a device can stream without end,
// and a folder is no file at all.
#pragma once

#include <filesystem>
#include <string>

namespace loom::formats {

// Throws loom::Error "cannot read <what> <path>: no such file" or "...: it is
// a FIFO (named pipe), not a regular file" (and so on for devices, sockets
// and folders), following symbolic links.
void require_regular_file(const std::filesystem::path& path, const std::string& what);

}  // namespace loom::formats
