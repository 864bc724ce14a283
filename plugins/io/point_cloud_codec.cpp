#include "point_cloud_codec.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "loom/atomic_file.hpp"
#include "loom/error.hpp"
#include "loom/image.hpp"

namespace loom::io {

std::vector<std::string> attribute_columns(const PointAttribute& attribute) {
  if (attribute.values.cols() == 1) return {attribute.name};
  std::vector<std::string> names;
  for (Eigen::Index k = 0; k < attribute.values.cols(); ++k) names.push_back(attribute.name + "_" + "xyz"[k]);
  return names;
}

std::string point_cloud_ply(const PointSet& points, const PointCloudFields& fields) {
  require_valid(points, "the points");
  const bool colors = fields.colors && points.has_colors();
  const bool radius = fields.radius && points.has_radius();
  const std::vector<PointAttribute> none;
  const std::vector<PointAttribute>& attributes = fields.attributes ? points.attributes : none;
  const std::string real = fields.double_precision ? "double" : "float";
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment written by Loom\nelement vertex " +
                    std::to_string(points.points()) + "\n";
  for (const char* axis : {"x", "y", "z"}) out += "property " + real + " " + axis + "\n";
  if (colors) out += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (radius) out += "property " + real + " radius\n";
  std::size_t columns = 3 + (radius ? 1 : 0);
  for (const PointAttribute& a : attributes)
    for (const std::string& name : attribute_columns(a)) {
      out += "property " + real + " " + name + "\n";
      ++columns;
    }
  out += "end_header\n";
  const std::size_t record = columns * (fields.double_precision ? 8 : 4) + (colors ? 3 : 0);
  out.reserve(out.size() + record * static_cast<std::size_t>(points.points()));
  auto put = [&out](auto value) {  // the host is little-endian (x86-64, aarch64)
    char b[sizeof value];
    std::memcpy(b, &value, sizeof value);
    out.append(b, sizeof value);
  };
  auto put_real = [&](double value) {
    if (fields.double_precision)
      put(value);
    else
      put(static_cast<float>(value));
  };
  for (int i = 0; i < points.points(); ++i) {
    for (int k = 0; k < 3; ++k) put_real(points.P(i, k));
    for (int k = 0; colors && k < 3; ++k) {
      // Linear colors are not range-checked by require_valid: clamp, NaN to 0.
      const double c = std::isfinite(points.C(i, k)) ? std::clamp(points.C(i, k), 0.0, 1.0) : 0.0;
      put(static_cast<std::uint8_t>(std::lround(255 * linear_to_srgb(static_cast<float>(c)))));
    }
    if (radius) put_real(points.radius[i]);
    for (const PointAttribute& a : attributes)
      for (Eigen::Index k = 0; k < a.values.cols(); ++k) put_real(a.values(i, k));
  }
  return out;
}

void write_point_cloud(const PointSet& points, const std::filesystem::path& path, const PointCloudFields& fields) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".ply") throw Error("cannot save " + path.string() + ": point clouds are written as .ply");
  write_file_atomic(path, point_cloud_ply(points, fields));
}

}  // namespace loom::io
