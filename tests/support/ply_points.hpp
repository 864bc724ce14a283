// A small reader of binary little-endian PLY point clouds (one vertex element
// of scalar float, double and uchar properties), written from the format's
// specification for tests: independent of the io plugin's writer and reader.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace loom::test {

struct PlyPoints {
  std::vector<std::string> properties;  // "float x", "uchar red", "double velocity_x", ...
  std::map<std::string, std::vector<double>> columns;  // by property name, the values in file order
  long count = 0;
};

// Reads the file; records a test failure (and returns what it read) when it is
// not such a PLY or has bytes after the last vertex.
PlyPoints read_ply_points(const std::filesystem::path& path);

}  // namespace loom::test
