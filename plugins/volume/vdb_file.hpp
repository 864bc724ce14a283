// A Volume as an OpenVDB file (.vdb), written atomically: a reader never sees
// half a file, and a failed write leaves the old one.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "volume.hpp"

namespace loom::volume {

// Writes the volume's grids (density, then velocity if any) with `metadata`
// as file-level string metadata ("loom:node", ...). Blosc-compressed as
// OpenVDB writes by default. The file's UUID, which OpenVDB draws at random,
// is made from the file's other bytes instead, so equal grids give equal
// files (decision 23): a frame written on a farm equals one written here.
void write_vdb(const Volume& volume, const std::filesystem::path& path,
               const std::vector<std::pair<std::string, std::string>>& metadata);

}  // namespace loom::volume
