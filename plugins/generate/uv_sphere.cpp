// UVSphere: a closed sphere of latitude rings and longitude segments.
#include <cmath>

#include "loom/mesh.hpp"
#include "loom/plugin.hpp"
#include "polar_mesh.hpp"

namespace {

struct UVSphere {
  static constexpr const char* name = "UVSphere";
  static void declare(loom::NodeSpec& s) {
    s.describe("A closed sphere (no boundary): two poles and rings-1 latitude rings, outward normals.")
        .input<double>("radius", 1.0, "radius").range(1e-9, 1e9)
        .input<int>("rings", 16, "latitude bands").range(2, 4096)
        .input<int>("segments", 32, "longitude segments").range(3, 65536)
        .output<loom::Mesh>("mesh", "the sphere");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    const double R = in.get<double>("radius");
    const int rings = in.get<int>("rings"), segs = in.get<int>("segments");
    loom::generate::require_polar_counts(rings, segs);
    loom::Mesh mesh;
    const int n = 2 + (rings - 1) * segs;
    mesh.V.resize(n, 3);
    mesh.N.resize(n, 3);
    mesh.V.row(0) << 0, 0, R;
    mesh.V.row(n - 1) << 0, 0, -R;
    auto index = [&](int ring, int s) { return 1 + (ring - 1) * segs + (s % segs); };
    for (int r = 1; r < rings; ++r)
      for (int s = 0; s < segs; ++s) {
        const double theta = M_PI * r / rings, phi = 2 * M_PI * s / segs;
        mesh.V.row(index(r, s)) << R * std::sin(theta) * std::cos(phi), R * std::sin(theta) * std::sin(phi),
            R * std::cos(theta);
      }
    mesh.F.resize(2 * segs * (rings - 1), 3);
    int f = 0;
    for (int s = 0; s < segs; ++s) {
      mesh.F.row(f++) << 0, index(1, s), index(1, s + 1);
      mesh.F.row(f++) << n - 1, index(rings - 1, s + 1), index(rings - 1, s);
    }
    for (int r = 1; r < rings - 1; ++r)
      for (int s = 0; s < segs; ++s) {
        mesh.F.row(f++) << index(r, s), index(r + 1, s), index(r + 1, s + 1);
        mesh.F.row(f++) << index(r, s), index(r + 1, s + 1), index(r, s + 1);
      }
    mesh.N = mesh.V / R;
    out.set("mesh", std::move(mesh));
  }
};
LOOM_NODE(UVSphere);

}  // namespace
