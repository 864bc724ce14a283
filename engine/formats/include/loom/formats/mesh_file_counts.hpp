// The element counts a mesh file declares in its header, checked against the
// file's size before any reader (Loom's own or assimp's) allocates for them:
// a 1 KB file that declares 2e9 vertices is refused with its name and the
// count, instead of ending in std::bad_alloc (or in tens of GB when the
// allocation succeeds).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>


namespace loom::formats {

// Throws loom::Error naming the file and the count when an OFF or PLY header,
// or a mesh block of a text DirectX .x file, declares more elements than the
// file has bytes for: an element takes at least one byte per value in binary
// and two (a digit and a separator) in text. `head` is the file's start, at
// least its header (the whole file for .x); `file_size` its size in bytes.
// The format is told by the content (ply, OFF/COFF/NOFF, xof ... txt); other
// files pass.
void check_declared_counts(std::string_view head, std::uintmax_t file_size, const std::string& file);

// The same for a file on disk (read as far as its format needs). Files that
// cannot be read pass: their readers report that.
void check_declared_counts(const std::filesystem::path& path);

}  // namespace loom::formats
