// SavePoints (plugin io) writing MPM particles as PLY point clouds, one file
// per frame, read back by tests/support's PLY reader, written from the
// format's specification (not the io plugin's reader, which takes meshes only).
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

#include <Eigen/LU>
#include <gtest/gtest.h>

#include "loom/image.hpp"
#include "loom/point_set.hpp"
#include "loom/testing.hpp"
#include "mpm_state.hpp"
#include "ply_points.hpp"
#include "point_cloud_codec.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

using test::PlyPoints;
using test::read_ply_points;

TEST(SavePoints, WritesEveryFramesParticlesAsAPlyPointCloud) {
  testing::Engine e;
  const json doc = json::parse(R"({"loom": 1, "time": {"start": 1, "end": 3, "fps": 30}, "nodes": {
    "emit": {"type": "MPMEmitBox", "inputs": {"dimension": 3, "min": [0.4, 0.5, 0.4], "max": [0.6, 0.7, 0.6],
             "material": "elastic", "sampling": "grid", "spacing": 0.04, "color": [0.2, 0.5, 1.0, 1]}},
    "sim": {"type": "MPMStep", "inputs": {"state": {"from": "emit.particles"}, "resolution": 16,
            "point_radius": 0.01}},
    "save": {"type": "SavePoints", "inputs": {"points": {"from": "sim.points"},
             "path": "pts/frame_{frame:04}.ply"}}}})");
  Graph g = e.load(doc);
  EvalOptions o;
  o.targets.push_back(parse_target("save"));
  o.targets.push_back(parse_target("sim.points"));
  o.frames = FrameRange{1, 3};
  o.output_dir = test::temp_dir();
  EvalResult r = e.session().evaluate(g, o);
  ASSERT_TRUE(r.ok());
  const auto& points = r.outputs.at("sim.points").at(0).as<PointSet>();
  ASSERT_GT(points.points(), 50);
  for (int f = 1; f <= 3; ++f)
    EXPECT_TRUE(std::filesystem::exists(o.output_dir / ("pts/frame_000" + std::to_string(f) + ".ply"))) << f;
  const PlyPoints ply = read_ply_points(o.output_dir / "pts/frame_0003.ply");
  EXPECT_EQ(ply.properties, (std::vector<std::string>{"float x", "float y", "float z", "uchar red", "uchar green",
                                                      "uchar blue", "float radius"}));
  ASSERT_EQ(ply.count, points.points());
  const char* axes[] = {"x", "y", "z"};
  const char* channels[] = {"red", "green", "blue"};
  for (int i = 0; i < points.points(); ++i) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(ply.columns.at(axes[k])[i], static_cast<float>(points.P(i, k)));
      // 8-bit sRGB of the linear color: within half a step after decoding.
      const float byte = static_cast<float>(ply.columns.at(channels[k])[i]);
      const double decoded = srgb_to_linear(byte / 255.0f);
      const double step = srgb_to_linear(std::min(1.0f, (byte + 1) / 255.0f)) - decoded;
      EXPECT_NEAR(decoded, points.C(i, k), step + 1e-6);
    }
    EXPECT_EQ(ply.columns.at("radius")[i], 0.01f);
  }
  // The particles fell between the frames: the files differ.
  const PlyPoints first = read_ply_points(o.output_dir / "pts/frame_0001.ply");
  EXPECT_GT(first.columns.at("y")[0], ply.columns.at("y")[0]);
}

TEST(SavePoints, OptionalFieldsAndBadInput) {
  PointSet p;
  p.P = Eigen::MatrixX3d::Random(4, 3);
  const auto dir = test::temp_dir();
  io::write_point_cloud(p, dir / "bare.ply", {});
  const PlyPoints bare = read_ply_points(dir / "bare.ply");
  EXPECT_EQ(bare.properties, (std::vector<std::string>{"float x", "float y", "float z"}));
  EXPECT_EQ(bare.count, 4);
  p.C = Eigen::MatrixX3d::Constant(4, 3, 0.5);
  p.radius = Eigen::VectorXd::Constant(4, 0.1);
  io::write_point_cloud(p, dir / "no_extras.ply", {false, false});
  EXPECT_EQ(read_ply_points(dir / "no_extras.ply").properties.size(), 3u);
  // An empty cloud is a valid file.
  io::write_point_cloud(PointSet{}, dir / "empty.ply", {});
  EXPECT_EQ(read_ply_points(dir / "empty.ply").count, 0);

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

// MPMPoints → SavePoints: every particle's velocity, mass, J, plastic strain
// and material in the file, read back and compared with the state the step
// returned (exactly in double precision, to float rounding in single).
TEST(SavePoints, ParticleAttributesRoundTripThroughThePly) {
  testing::Engine e;
  const json doc = json::parse(R"({"loom": 1, "time": {"start": 1, "end": 2, "fps": 30}, "nodes": {
    "sand": {"type": "MPMEmitBox", "inputs": {"min": [0.3, 0.3, 0], "max": [0.5, 0.5, 0], "material": "sand",
             "sampling": "grid", "spacing": 0.02, "velocity": [1, -2, 0]}},
    "emit": {"type": "MPMEmitBox", "inputs": {"particles": {"from": "sand.particles"}, "min": [0.6, 0.3, 0],
             "max": [0.7, 0.4, 0], "material": "fluid", "sampling": "grid", "spacing": 0.02}},
    "sim": {"type": "MPMStep", "inputs": {"state": {"from": "emit.particles"}, "resolution": 32}},
    "pts": {"type": "MPMPoints", "inputs": {"state": {"from": "sim.state"}}},
    "exact": {"type": "SavePoints", "inputs": {"points": {"from": "pts.points"}, "double_precision": true,
              "path": "exact_{frame:04}.ply"}},
    "single": {"type": "SavePoints", "inputs": {"points": {"from": "pts.points"}, "path": "single_{frame:04}.ply"}}}})");
  Graph g = e.load(doc);
  EvalOptions o;
  for (const char* t : {"exact", "single", "sim.state"}) o.targets.push_back(parse_target(t));
  o.frames = FrameRange{1, 2};
  o.output_dir = test::temp_dir();
  EvalResult r = e.session().evaluate(g, o);
  ASSERT_TRUE(r.ok());
  const auto& state = r.outputs.at("sim.state").back().as<mpm::MpmState>();
  const mpm::Particles<2>& p = state.p2;
  ASSERT_GT(p.size(), 50);
  const PlyPoints exact = read_ply_points(o.output_dir / "exact_0002.ply");
  const PlyPoints single = read_ply_points(o.output_dir / "single_0002.ply");
  ASSERT_EQ(exact.count, p.size());
  EXPECT_EQ(exact.properties.front(), "double x");
  EXPECT_EQ(single.properties.front(), "float x");
  int sand = 0, fluid = 0;
  for (int i = 0; i < p.size(); ++i) {
    const bool is_sand = p.material[i] == mpm::Material::sand;
    sand += is_sand;
    fluid += !is_sand;
    const double J = is_sand ? p.F[i].determinant() : p.J[i];
    const double strain = is_sand ? p.q[i] : 0.0;
    const std::pair<const char*, double> expected[] = {
        {"x", p.x[i].x()},       {"y", p.x[i].y()},   {"velocity_x", p.v[i].x()}, {"velocity_y", p.v[i].y()},
        {"velocity_z", 0.0},     {"mass", p.mass[i]}, {"volume", p.volume[i]},     {"J", J},
        {"plastic_strain", strain}, {"material", static_cast<double>(p.material[i])}};
    for (const auto& [name, value] : expected) {
      EXPECT_EQ(exact.columns.at(name)[i], value) << name << " of particle " << i;
      EXPECT_EQ(single.columns.at(name)[i], static_cast<float>(value)) << name << " of particle " << i;
    }
  }
  EXPECT_GT(sand, 0);
  EXPECT_GT(fluid, 0);
  // The sand moved: its velocities are not the emitter's any more but are not zero.
  EXPECT_NE(exact.columns.at("velocity_x")[0], 0.0);
}

TEST(SavePoints, AttributesAreCheckedAndCanBeLeftOut) {
  PointSet p;
  p.P = Eigen::MatrixX3d::Random(3, 3);
  p.attributes = {{"mass", Eigen::VectorXd::Constant(3, 2.0)}, {"v", Eigen::MatrixXd::Random(3, 2)}};
  const auto dir = test::temp_dir();
  io::write_point_cloud(p, dir / "a.ply", {});
  EXPECT_EQ(read_ply_points(dir / "a.ply").properties,
            (std::vector<std::string>{"float x", "float y", "float z", "float mass", "float v_x", "float v_y"}));
  io::PointCloudFields none;
  none.attributes = false;
  io::write_point_cloud(p, dir / "b.ply", none);
  EXPECT_EQ(read_ply_points(dir / "b.ply").properties.size(), 3u);
  auto refused = [&](PointSet bad, const std::string& words) {
    try {
      io::write_point_cloud(bad, dir / "bad.ply", {});
      ADD_FAILURE() << "accepted: " << words;
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find(words), std::string::npos) << error.what();
    }
    EXPECT_FALSE(std::filesystem::exists(dir / "bad.ply"));
  };
  PointSet bad = p;
  bad.attributes[0].values.resize(2, 1);
  refused(bad, "\"mass\" has 2 rows for 3 points");
  bad = p;
  bad.attributes[1].values(1, 1) = std::nan("");
  refused(bad, "\"v\" has NaN");
  bad = p;
  bad.attributes[1].name = "mass";
  refused(bad, "\"mass\" is given twice");
  bad = p;
  bad.attributes[0].values = Eigen::MatrixXd::Zero(3, 4);
  refused(bad, "4 columns");
}

}  // namespace
}  // namespace loom
