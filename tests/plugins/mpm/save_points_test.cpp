// SavePoints (plugin io) writing MPM particles as PLY point clouds, one file
// per frame, read back by a small PLY reader written here from the format's
// specification (not the io plugin's reader, which takes meshes only).
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "loom/image.hpp"
#include "loom/point_set.hpp"
#include "loom_test.hpp"
#include "point_cloud_codec.hpp"

namespace loom {
namespace {

struct PlyPoints {
  std::vector<std::string> properties;  // "float x", "uchar red", ...
  std::vector<float> xyz, radius;
  std::vector<std::uint8_t> rgb;
};

// Binary little-endian PLY with one vertex element of float and uchar
// scalar properties, no other element.
PlyPoints read_ply_points(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string bytes = ss.str();
  const std::size_t end = bytes.find("end_header\n");
  EXPECT_NE(end, std::string::npos);
  std::istringstream header(bytes.substr(0, end));
  std::string line, word;
  std::getline(header, line);
  EXPECT_EQ(line, "ply");
  PlyPoints p;
  long count = -1;
  while (std::getline(header, line)) {
    std::istringstream ls(line);
    ls >> word;
    if (word == "format") {
      ls >> word;
      EXPECT_EQ(word, "binary_little_endian");
    } else if (word == "element") {
      ls >> word >> count;
      EXPECT_EQ(word, "vertex");
    } else if (word == "property") {
      std::string type, name;
      ls >> type >> name;
      p.properties.push_back(type + " " + name);
    }
  }
  std::size_t at = end + 11;
  for (long i = 0; i < count; ++i)
    for (const std::string& prop : p.properties) {
      if (prop.rfind("float", 0) == 0) {
        float v;
        std::memcpy(&v, bytes.data() + at, 4);
        at += 4;
        (prop == "float radius" ? p.radius : p.xyz).push_back(v);
      } else {
        p.rgb.push_back(static_cast<std::uint8_t>(bytes[at]));
        at += 1;
      }
    }
  EXPECT_EQ(at, bytes.size()) << "bytes after the last vertex";
  return p;
}

TEST(SavePoints, WritesEveryFramesParticlesAsAPlyPointCloud) {
  test::Engine e;
  const json doc = json::parse(R"({"loom": 1, "time": {"start": 1, "end": 3, "fps": 30}, "nodes": {
    "emit": {"type": "MPMEmitBox", "inputs": {"dimension": 3, "min": [0.4, 0.5, 0.4], "max": [0.6, 0.7, 0.6],
             "material": "elastic", "sampling": "grid", "spacing": 0.04, "color": [0.2, 0.5, 1.0, 1]}},
    "sim": {"type": "MPMStep", "inputs": {"state": {"from": "emit.particles"}, "resolution": 16,
            "point_radius": 0.01}},
    "save": {"type": "SavePoints", "inputs": {"points": {"from": "sim.points"},
             "path": "pts/frame_{frame:04}.ply"}}}})");
  Graph g = e.graph(doc);
  EvalOptions o;
  o.targets.push_back(parse_target("save"));
  o.targets.push_back(parse_target("sim.points"));
  o.frames = FrameRange{1, 3};
  o.output_dir = test::temp_dir();
  EvalResult r = e.session.evaluate(g, o);
  ASSERT_TRUE(r.ok());
  const auto& points = r.outputs.at("sim.points").at(0).as<PointSet>();
  ASSERT_GT(points.points(), 50);
  for (int f = 1; f <= 3; ++f)
    EXPECT_TRUE(std::filesystem::exists(o.output_dir / ("pts/frame_000" + std::to_string(f) + ".ply"))) << f;
  const PlyPoints ply = read_ply_points(o.output_dir / "pts/frame_0003.ply");
  EXPECT_EQ(ply.properties, (std::vector<std::string>{"float x", "float y", "float z", "uchar red", "uchar green",
                                                      "uchar blue", "float radius"}));
  ASSERT_EQ(ply.xyz.size(), 3u * points.points());
  ASSERT_EQ(ply.rgb.size(), 3u * points.points());
  ASSERT_EQ(ply.radius.size(), static_cast<std::size_t>(points.points()));
  for (int i = 0; i < points.points(); ++i) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(ply.xyz[3 * i + k], static_cast<float>(points.P(i, k)));
      // 8-bit sRGB of the linear color: within half a step after decoding.
      const double decoded = srgb_to_linear(ply.rgb[3 * i + k] / 255.0f);
      const double step = srgb_to_linear(std::min(1.0f, (ply.rgb[3 * i + k] + 1) / 255.0f)) - decoded;
      EXPECT_NEAR(decoded, points.C(i, k), step + 1e-6);
    }
    EXPECT_EQ(ply.radius[i], 0.01f);
  }
  // The particles fell between the frames: the files differ.
  const PlyPoints first = read_ply_points(o.output_dir / "pts/frame_0001.ply");
  EXPECT_GT(first.xyz[1], ply.xyz[1]);
}

TEST(SavePoints, OptionalFieldsAndBadInput) {
  PointSet p;
  p.P = Eigen::MatrixX3d::Random(4, 3);
  const auto dir = test::temp_dir();
  io::write_point_cloud(p, dir / "bare.ply", {});
  const PlyPoints bare = read_ply_points(dir / "bare.ply");
  EXPECT_EQ(bare.properties, (std::vector<std::string>{"float x", "float y", "float z"}));
  EXPECT_EQ(bare.xyz.size(), 12u);
  p.C = Eigen::MatrixX3d::Constant(4, 3, 0.5);
  p.radius = Eigen::VectorXd::Constant(4, 0.1);
  io::write_point_cloud(p, dir / "no_extras.ply", {false, false});
  EXPECT_EQ(read_ply_points(dir / "no_extras.ply").properties.size(), 3u);
  // An empty cloud is a valid file.
  io::write_point_cloud(PointSet{}, dir / "empty.ply", {});
  EXPECT_TRUE(read_ply_points(dir / "empty.ply").xyz.empty());

  EXPECT_THROW(io::write_point_cloud(p, dir / "points.obj", {}), Error);
  p.P(2, 1) = std::nan("");
  try {
    io::write_point_cloud(p, dir / "nan.ply", {});
    ADD_FAILURE() << "a NaN position was written";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("points"), std::string::npos) << error.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "nan.ply"));
}

}  // namespace
}  // namespace loom
