// Point clouds -> PLY files (binary little-endian): one vertex element with
// float x y z, optionally uchar red green blue (the PointSet's linear colors
// sRGB-encoded, as viewers such as MeshLab and CloudCompare show them) and a
// float radius. No face element: LoadMesh, which reads triangle meshes,
// refuses such a file; point-cloud tools read it.
#pragma once

#include <filesystem>
#include <string>

#include "loom/point_set.hpp"

namespace loom::io {

struct PointCloudFields {
  bool colors = true;  // written only when the point set has colors
  bool radius = true;  // written only when the point set has radii
};

// The file's bytes. Throws loom::Error if the point set is invalid
// (non-finite positions, rows that do not match).
std::string point_cloud_ply(const PointSet& points, const PointCloudFields& fields);

// Writes point_cloud_ply atomically (a reader never sees half a file).
void write_point_cloud(const PointSet& points, const std::filesystem::path& path, const PointCloudFields& fields);

}  // namespace loom::io
