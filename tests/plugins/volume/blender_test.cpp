// Blender opens what Loom writes for it: a multi-layer EXR (SaveLayers'
// codec) and an OpenVDB file (SaveVDB's), checked by running Blender
// headless (blender_check.py) and comparing what it reads with what Loom
// wrote. Skipped, saying so, where Blender is not installed (it is optional:
// Debian's blender package, about 90 MB).
#include <filesystem>
#include <map>
#include <sstream>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "bspline_splat.hpp"
#include "image_codec.hpp"
#include "noise_image.hpp"
#include "run_loom.hpp"
#include "test_files.hpp"
#include "vdb_file.hpp"

namespace loom {
namespace {

namespace fs = std::filesystem;

Image noise(int channels, float low, float high, int seed) {
  return test::noise_image(12, 20, channels, low, high, seed);
}

// Particles on a grid of spacing s filling [lo, hi] (a box of water).
Eigen::MatrixX3d box_points(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double s) {
  std::vector<Eigen::Vector3d> p;
  for (double x = lo.x(); x <= hi.x() + 1e-9; x += s)
    for (double y = lo.y(); y <= hi.y() + 1e-9; y += s)
      for (double z = lo.z(); z <= hi.z() + 1e-9; z += s) p.emplace_back(x, y, z);
  Eigen::MatrixX3d m(static_cast<Eigen::Index>(p.size()), 3);
  for (std::size_t i = 0; i < p.size(); ++i) m.row(static_cast<Eigen::Index>(i)) = p[i];
  return m;
}

TEST(Blender, OpensTheMultiLayerExrAndTheVdbWithLoomsValues) {
  std::string out;
  if (test::run_shell("command -v blender", &out) != 0)
    GTEST_SKIP() << "blender is not installed (optional: apt-get install blender)";
  const fs::path dir = test::temp_dir();
  const std::vector<io::NamedImage> layers = {{"image", noise(3, 0, 8, 1), {"R", "G", "B"}},
                                              {"albedo", noise(3, 0, 1, 2), {"R", "G", "B"}},
                                              {"normal", noise(3, -1, 1, 3), {"X", "Y", "Z"}},
                                              {"depth", noise(1, 0, 50, 4), {"Z"}}};
  io::write_layers(layers, dir / "aov.exr", false, false, false, {});
  // A box of particles; the density inside is m / s³ (s: the spacing).
  const double h = 0.02, s = h / 2, m = 1e-3;
  const Eigen::Vector3d lo(0.3, 0.4, 0.3), hi(0.6, 0.7, 0.5);
  const Eigen::MatrixX3d x = box_points(lo, hi, s);
  volume::write_vdb(
      volume::splat_points(x, Eigen::VectorXd::Constant(x.rows(), m), Eigen::MatrixX3d::Zero(x.rows(), 3), h),
      dir / "water.vdb", {});
  const double inside = m / (s * s * s);
  const std::string script = std::string(LOOM_SOURCE_DIR) + "/tests/plugins/volume/blender_check.py";
  ASSERT_EQ(test::run_shell("blender -b --factory-startup --python " + script + " -- " + (dir / "aov.exr").string() +
                                " " + (dir / "water.vdb").string() + " " + dir.string() + " " +
                                std::to_string(inside / 2) + " " + std::to_string(layers[0].image.width()) + " " +
                                std::to_string(layers[0].image.height()) + " 2>&1",
                            &out),
            0)
      << out;
  std::map<std::string, std::string> found;  // first word of each line Blender printed → the rest
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);) {
    const auto space = line.find(' ');
    if (space != std::string::npos) found[line.substr(0, space)] += line.substr(space + 1) + "\n";
  }
  // Every layer is a pass of Blender's Image node, with Loom's values.
  for (const auto& l : layers) {
    EXPECT_NE(found["LAYERS"].find(l.name), std::string::npos) << l.name << " not in " << found["LAYERS"];
    const Image back = io::read_image(dir / (l.name + ".exr"), io::Decode::linear);
    std::vector<cv::Mat> wrote, read;
    cv::split(l.image.pixels, wrote);
    cv::split(back.pixels, read);
    ASSERT_EQ(back.width(), l.image.width()) << l.name;
    for (std::size_t c = 0; c < 3; ++c)  // a one-channel layer comes back as grey RGB
      EXPECT_LT(cv::norm(read[c], wrote[std::min(c, wrote.size() - 1)], cv::NORM_INF), 1e-6) << l.name << " " << c;
  }
  EXPECT_NE(found["GRID"].find("density FLOAT"), std::string::npos) << out;
  EXPECT_NE(found["GRID"].find("velocity VECTOR_FLOAT"), std::string::npos) << out;
  // Volume to Mesh at half the inside density outlines the box (particles
  // reach s/2 past the outer ones) to within a voxel. Blender puts voxel i's
  // centre at (i + ½)h, where OpenVDB puts it at i·h: its half-voxel shift.
  std::istringstream bounds(found["BOUNDS"]);
  Eigen::Vector3d bmin, bmax;
  bounds >> bmin.x() >> bmin.y() >> bmin.z() >> bmax.x() >> bmax.y() >> bmax.z();
  ASSERT_TRUE(bounds) << out;
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(bmin[k], lo[k] - s / 2 + h / 2, h) << k;
    EXPECT_NEAR(bmax[k], hi[k] + s / 2 + h / 2, h) << k;
  }
}

}  // namespace
}  // namespace loom
