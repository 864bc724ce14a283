// The pictures of docs/mpm.md: the example scenes simulated through the solver
// library and splatted, several instants side by side in one strip each.
// (The graphs in graphs/ describe the same scenes for the engine's frames.)
//   bench_mpm_pictures [--out FOLDER] [scene ...]   default: docs/images/mpm, every scene
//   (scenes: mpm88 mpm99 colliders 3d)
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "bench_harness.hpp"
#include "emitters.hpp"
#include "mls_mpm.hpp"
#include "particle_splat.hpp"

namespace {

using namespace loom::mpm;

template <int D>
Particles<D> emit(const std::function<bool(const Eigen::Matrix<double, D, 1>&)>& inside,
                  Eigen::Matrix<double, D, 1> lo, Eigen::Matrix<double, D, 1> hi, Material m, double E,
                  double nu, Eigen::Vector3f color, EmitOptions o) {
  o.material = m, o.E = E, o.nu = nu, o.color = color;
  return fill_shape<D>(inside, lo, hi, o);
}

cv::Mat to_srgb8(const cv::Mat& linear) {
  cv::Mat out(linear.size(), CV_8UC3);
  for (int y = 0; y < linear.rows; ++y)
    for (int x = 0; x < linear.cols; ++x)
      for (int k = 0; k < 3; ++k) {
        const float c = std::clamp(linear.at<cv::Vec3f>(y, x)[k], 0.0f, 1.0f);
        const float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1 / 2.4f) - 0.055f;
        out.at<cv::Vec3b>(y, x)[2 - k] = static_cast<unsigned char>(std::lround(255 * s));
      }
  return out;
}

template <int D>
void strip(const std::filesystem::path& file, MpmState state, const Settings& settings,
           const std::vector<double>& times, SplatOptions splat_options) {
  Solver<D> solver(settings);
  auto& ps = [&]() -> Particles<D>& {
    if constexpr (D == 2) return state.p2; else return state.p3;
  }();
  std::vector<cv::Mat> tiles;
  double t = 0;
  for (double target : times) {
    if (target > t) {
      const auto r = solver.advance(ps, target - t);
      std::printf("%s: t = %.2f s after %d substeps\n", file.filename().c_str(), target, r.substeps);
      t = target;
    }
    cv::Mat tile = to_srgb8(splat(state, splat_options));
    cv::putText(tile, "t = " + std::to_string(t).substr(0, 4) + " s", cv::Point(10, 28),
                cv::FONT_HERSHEY_SIMPLEX, 0.7, cv::Scalar(230, 230, 230), 1, cv::LINE_AA);
    tiles.push_back(tile);
  }
  cv::Mat row;
  cv::hconcat(tiles, row);
  cv::imwrite(file.string(), row, {cv::IMWRITE_PNG_COMPRESSION, 9});
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  loom::bench::Cli cli("bench_mpm_pictures",
                       "The figures of docs/mpm.md: the example scenes simulated and splatted, several "
                       "instants side by side.");
  std::vector<std::string> scenes;
  cli.results(loom::bench::source_dir() / "docs/images/mpm", "The figures").modes(scenes,
            {{"mpm88", "mpm88's fluid block"},
             {"mpm99", "fluid, jelly, snow and sand"},
             {"colliders", "a jelly disk, a snowball and sand onto a slanted plane and a round peg"},
             {"3d", "an elastic ball and a sand block onto a sphere collider"}},
            "scenes to simulate (default: all)");
  cli.parse(argc, argv);
  const std::filesystem::path dir = loom::bench::results_dir();
  std::filesystem::create_directories(dir);
  auto want = [&](const std::string& scene) { return loom::bench::wants(scenes, scene); };
  SplatOptions splat;
  splat.width = 256;
  splat.radius_px = 0.9;
  using V2 = Eigen::Vector2d;
  using V3 = Eigen::Vector3d;
  auto all2 = [](const V2&) { return true; };
  auto all3 = [](const V3&) { return true; };
  if (want("mpm88")) {
    EmitOptions o;
    o.sampling = Sampling::random, o.count = 8192, o.particle_volume = std::pow(0.5 / 128, 2);
    MpmState s;
    s.p2 = emit<2>(all2, V2(0.2, 0.2), V2(0.6, 0.6), Material::fluid, 400, 0, {0.07f, 0.35f, 0.8f}, o);
    Settings settings;
    settings.dt_max = 2e-4, settings.cfl = 1.0;
    strip<2>(dir / "mpm88.png", s, settings, {0, 0.3, 0.6, 1.5}, splat);
  }
  if (want("mpm99")) {  // + sand
    EmitOptions o;
    o.sampling = Sampling::random, o.count = 3000, o.particle_volume = std::pow(0.5 / 128, 2);
    MpmState s;
    s.p2 = emit<2>(all2, V2(0.3, 0.05), V2(0.5, 0.25), Material::fluid, 1388.9, 0.2, {0.07f, 0.35f, 0.8f}, o);
    o.seed = 2;
    s.p2.append(emit<2>(all2, V2(0.4, 0.37), V2(0.6, 0.57), Material::elastic, 1500, 0.2, {0.9f, 0.25f, 0.2f}, o));
    o.seed = 3;
    s.p2.append(emit<2>(all2, V2(0.5, 0.69), V2(0.7, 0.89), Material::snow, 5000, 0.2, {0.9f, 0.9f, 0.9f}, o));
    o.seed = 4;
    s.p2.append(emit<2>(all2, V2(0.08, 0.6), V2(0.28, 0.8), Material::sand, 5000, 0.3, {0.8f, 0.6f, 0.25f}, o));
    Settings settings;
    settings.gravity = V3(0, -50, 0), settings.dt_max = 1e-4;
    strip<2>(dir / "mpm99.png", s, settings, {0, 0.15, 0.3, 0.8}, splat);
  }
  if (want("colliders")) {  // a jelly disk, a snowball and sand onto a slanted plane and a round peg
    EmitOptions o;
    o.spacing = 0.004;
    MpmState s;
    const V2 a(0.3, 0.8), b(0.62, 0.75);
    s.p2 = emit<2>([&](const V2& x) { return (x - a).norm() <= 0.08; }, a.array() - 0.08, a.array() + 0.08,
                   Material::elastic, 2000, 0.3, {0.9f, 0.25f, 0.2f}, o);
    s.p2.append(emit<2>([&](const V2& x) { return (x - b).norm() <= 0.07; }, b.array() - 0.07,
                        b.array() + 0.07, Material::snow, 8000, 0.2, {0.92f, 0.92f, 0.95f}, o));
    o.sampling = Sampling::poisson;
    s.p2.append(emit<2>(all2, V2(0.1, 0.55), V2(0.2, 0.7), Material::sand, 5000, 0.3, {0.8f, 0.6f, 0.25f}, o));
    Settings settings;
    settings.walls = Boundary::sticky;
    Collider plane, peg;
    plane.point = V3(0, 0.45, 0), plane.normal = V3(0.3, 1, 0).normalized();
    peg.shape = Collider::Shape::sphere, peg.point = V3(0.62, 0.45, 0), peg.radius = 0.06;
    peg.boundary = Boundary::sticky;
    settings.colliders = {plane, peg};
    strip<2>(dir / "mpm-colliders.png", s, settings, {0, 0.25, 0.5, 1.2}, splat);
  }
  if (want("3d")) {  // an elastic ball and a sand block onto a sphere collider
    EmitOptions o;
    o.spacing = 0.0125;
    MpmState s;
    s.dim = 3;
    const V3 c(0.35, 0.7, 0.5);
    s.p3 = emit<3>([&](const V3& x) { return (x - c).norm() <= 0.12; }, c.array() - 0.12,
                   c.array() + 0.12, Material::elastic, 2000, 0.3, {0.85f, 0.2f, 0.15f}, o);
    s.p3.append(emit<3>(all3, V3(0.5, 0.45, 0.35), V3(0.75, 0.7, 0.65), Material::sand, 3000, 0.3,
                        {0.85f, 0.65f, 0.3f}, o));
    Settings settings;
    settings.resolution = 48, settings.walls = Boundary::slip;
    Collider sphere;
    sphere.shape = Collider::Shape::sphere, sphere.point = V3(0.5, 0.25, 0.5), sphere.radius = 0.12;
    settings.colliders = {sphere};
    splat.radius_px = 1.6;
    strip<3>(dir / "mpm-3d.png", s, settings, {0, 0.2, 0.4, 0.8}, splat);
  }
}
