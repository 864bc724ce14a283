// PointsToVolume and SaveVDB, checked against what does not come from them:
// the quadratic B-spline written from its piecewise definition, the
// particles' own mass and momentum (conservation), OpenVDB's reader and
// vdb_print (libopenvdb-tools) for what a file holds.
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include "bspline_splat.hpp"
#include "loom/testing.hpp"
#include "run_loom.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

namespace fs = std::filesystem;

// The cardinal quadratic B-spline N(u) by its pieces (|u| < ½, ½ ≤ |u| < 3/2).
double bspline(double u) {
  u = std::abs(u);
  if (u < 0.5) return 0.75 - u * u;
  if (u < 1.5) return 0.5 * (1.5 - u) * (1.5 - u);
  return 0;
}

TEST(PointsToVolume, OneParticleSplatsTheAnalyticBSplineWeights) {
  const double h = 0.1, m = 2.5;
  Eigen::MatrixX3d x(1, 3), v(1, 3);
  x << 0.123, -0.456, 0.789;
  v << 1, -2, 3;
  const volume::Volume vol = volume::splat_points(x, Eigen::VectorXd::Constant(1, m), v, h);
  ASSERT_TRUE(vol.density && vol.velocity);
  EXPECT_EQ(vol.density->getName(), "density");
  EXPECT_EQ(vol.density->activeVoxelCount(), 27u);  // the 3×3×3 stencil, nothing else
  EXPECT_EQ(vol.velocity->activeVoxelCount(), 27u);
  double total = 0;
  for (auto it = vol.density->cbeginValueOn(); it; ++it) {
    const openvdb::Coord c = it.getCoord();
    const double w = bspline(x(0, 0) / h - c.x()) * bspline(x(0, 1) / h - c.y()) * bspline(x(0, 2) / h - c.z());
    EXPECT_GT(w, 0) << c;
    EXPECT_NEAR(*it * h * h * h, m * w, 1e-6 * m) << c;
    total += *it * h * h * h;
    // One particle: every voxel it reaches moves with it.
    const openvdb::Vec3s u = vol.velocity->tree().getValue(c);
    EXPECT_FLOAT_EQ(u.x(), 1);
    EXPECT_FLOAT_EQ(u.y(), -2);
    EXPECT_FLOAT_EQ(u.z(), 3);
  }
  EXPECT_NEAR(total, m, 1e-6 * m);
  // World position of voxel (i, j, k) is (i, j, k)·h: the transform says so.
  const openvdb::Vec3d p = vol.density->transform().indexToWorld(openvdb::Coord(1, -5, 8));
  EXPECT_NEAR(p.x(), 0.1, 1e-12);
  EXPECT_NEAR(p.y(), -0.5, 1e-12);
  EXPECT_NEAR(p.z(), 0.8, 1e-12);
}

TEST(PointsToVolume, NoVelocityAttributeNoVelocityGrid) {
  Eigen::MatrixX3d x = Eigen::MatrixX3d::Random(10, 3);
  const volume::Volume vol = volume::splat_points(x, Eigen::VectorXd::Ones(10), {}, 0.05);
  EXPECT_TRUE(vol.density);
  EXPECT_FALSE(vol.velocity);
}

// A 3D MPM water block after a few frames, as points, as grids, as files.
const char* kGraph = R"({"loom": 1, "time": {"start": 1, "end": 3, "fps": 30}, "nodes": {
  "emit": {"type": "MPMEmitBox", "inputs": {"dimension": 3, "min": [0.3, 0.4, 0.3], "max": [0.6, 0.7, 0.5],
           "material": "fluid", "sampling": "grid", "spacing": 0.03}},
  "sim": {"type": "MPMStep", "inputs": {"state": {"from": "emit.particles"}, "resolution": 24}},
  "points": {"type": "MPMPoints", "inputs": {"state": {"from": "sim.state"}}},
  "volume": {"type": "PointsToVolume", "inputs": {"points": {"from": "points.points"}, "voxel_size": 0.04}},
  "save": {"type": "SaveVDB", "inputs": {"volume": {"from": "volume.volume"}, "path": "vdb/water_{frame:04}.vdb"}}}})";

struct Sequence {
  EvalResult result;
  fs::path dir;
};

Sequence run_sequence(testing::Engine& e) {
  Graph g = e.load(json::parse(kGraph));
  EvalOptions o;
  o.targets = {parse_target("save"), parse_target("points.points")};
  o.frames = FrameRange{1, 3};
  o.output_dir = test::temp_dir() / "out";
  return {e.session().evaluate(g, o), o.output_dir};
}

openvdb::GridPtrVecPtr read_grids(const fs::path& file, openvdb::MetaMap::Ptr* meta = nullptr) {
  openvdb::initialize();
  openvdb::io::File f(file.string());
  f.open();
  openvdb::GridPtrVecPtr grids = f.getGrids();
  if (meta) *meta = f.getMetadata();
  f.close();
  return grids;
}

TEST(SaveVDB, TheDensityHoldsTheParticlesMassAndMomentum) {
  testing::Engine e;
  const Sequence s = run_sequence(e);
  ASSERT_TRUE(s.result.ok());
  const auto& points = s.result.outputs.at("points.points").at(0).as<PointSet>();  // the last frame, 3
  Eigen::VectorXd mass;
  Eigen::MatrixXd velocity;
  for (const auto& a : points.attributes) {
    if (a.name == "mass") mass = a.values.col(0);
    if (a.name == "velocity") velocity = a.values;
  }
  ASSERT_EQ(mass.size(), points.points());
  openvdb::MetaMap::Ptr meta;
  const auto grids = read_grids(s.dir / "vdb/water_0003.vdb", &meta);
  ASSERT_EQ(grids->size(), 2u);
  auto density = openvdb::gridPtrCast<openvdb::FloatGrid>((*grids)[0]);
  auto grid_velocity = openvdb::gridPtrCast<openvdb::Vec3SGrid>((*grids)[1]);
  ASSERT_TRUE(density && grid_velocity);
  const double h = density->voxelSize().x(), cell = h * h * h;
  EXPECT_DOUBLE_EQ(h, 0.04);
  double grid_mass = 0;
  Eigen::Vector3d grid_momentum = Eigen::Vector3d::Zero();
  for (auto it = density->cbeginValueOn(); it; ++it) {
    grid_mass += *it * cell;
    const openvdb::Vec3s u = grid_velocity->tree().getValue(it.getCoord());
    grid_momentum += *it * cell * Eigen::Vector3d(u.x(), u.y(), u.z());
  }
  EXPECT_NEAR(grid_mass, mass.sum(), 1e-6 * mass.sum());
  // Momentum: P2G conserves it exactly; floats keep it to ~1e-6 of Σ m|v|.
  const Eigen::Vector3d momentum = velocity.transpose() * mass;
  const double scale = (velocity.rowwise().norm().array() * mass.array()).sum();
  ASSERT_GT(scale, 0);  // the water fell: there is momentum to compare
  EXPECT_LT((grid_momentum - momentum).norm(), 1e-5 * scale);
  EXPECT_EQ(meta->metaValue<std::string>("loom:node"), "save");
  EXPECT_EQ(meta->metaValue<std::string>("loom:frame"), "3");
}

TEST(SaveVDB, EqualGridsGiveEqualFilesAndVdbPrintListsThem) {
  testing::Engine a, b;
  const Sequence first = run_sequence(a), second = run_sequence(b);
  ASSERT_TRUE(first.result.ok() && second.result.ok());
  for (int f = 1; f <= 3; ++f) {
    const std::string name = "vdb/water_000" + std::to_string(f) + ".vdb";
    const std::string bytes = test::read_text(first.dir / name);
    ASSERT_GT(bytes.size(), 100u) << name;
    EXPECT_EQ(bytes, test::read_text(second.dir / name)) << name;  // OpenVDB's UUID would differ
  }
  EXPECT_NE(test::read_text(first.dir / "vdb/water_0001.vdb"), test::read_text(first.dir / "vdb/water_0003.vdb"));
  std::string listing;
  if (test::run_shell("vdb_print -l " + (first.dir / "vdb/water_0002.vdb").string(), &listing) == 127)
    GTEST_SKIP() << "vdb_print (libopenvdb-tools) is not installed";
  EXPECT_NE(listing.find("Name: density"), std::string::npos) << listing;
  EXPECT_NE(listing.find("Name: velocity"), std::string::npos) << listing;
  EXPECT_NE(listing.find("Tree_float_5_4_3"), std::string::npos) << listing;
  EXPECT_NE(listing.find("Tree_vec3s_5_4_3"), std::string::npos) << listing;
  EXPECT_NE(listing.find("fog volume"), std::string::npos) << listing;
}

TEST(PointsToVolume, RefusesPointsBeyondItsCoordinatesAndTinyVoxels) {
  Eigen::MatrixX3d x(1, 3);
  x << 5000, 0, 0;  // 5e9 voxels of 1e-6: past OpenVDB's 32-bit coordinates
  try {
    volume::splat_points(x, Eigen::VectorXd::Ones(1), {}, 1e-6);
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("raise voxel_size"), std::string::npos) << e.what();
  }
  testing::Engine e;
  testing::GraphBuilder g;
  g.node("points", "MPMEmitBox").set("dimension", 3).set("spacing", 0.05);
  g.node("pts", "MPMPoints").link("state", "points.particles");
  g.node("vol", "PointsToVolume").link("points", "pts.points").set("voxel_size", 1e-9);
  try {
    e.load(g.document());
    FAIL() << "accepted";
  } catch (const GraphError& error) {
    EXPECT_NE(std::string(error.what()).find("/nodes/vol/inputs/voxel_size"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace loom
