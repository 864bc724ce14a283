// Point clouds -> PLY files (binary little-endian): one vertex element with
// float x y z, optionally uchar red green blue (the PointSet's linear colors
// sRGB-encoded, as viewers such as MeshLab and CloudCompare show them), a
// float radius and the named attributes (one property per column: "mass",
// or "velocity_x velocity_y velocity_z"). With `double_precision` positions,
// radius and attributes are 64-bit doubles (the values exactly). No face element: LoadMesh, which reads triangle meshes,
// refuses such a file; point-cloud tools read it.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "loom/point_set.hpp"

namespace loom::io {

struct PointCloudFields {
  bool colors = true;  // written only when the point set has colors
  bool radius = true;  // written only when the point set has radii
  bool attributes = true;
  bool double_precision = false;
};

// The PLY property names of an attribute's columns: its name for one
// column, name_x name_y (name_z) for two or three.
std::vector<std::string> attribute_columns(const PointAttribute& attribute);

// The file's bytes. Throws loom::Error if the point set is invalid
// (non-finite positions, rows that do not match).
std::string point_cloud_ply(const PointSet& points, const PointCloudFields& fields);

// Writes point_cloud_ply atomically (a reader never sees half a file).
void write_point_cloud(const PointSet& points, const std::filesystem::path& path, const PointCloudFields& fields);

}  // namespace loom::io
