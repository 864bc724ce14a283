#include "emit_inputs.hpp"

#include "loom/error.hpp"

namespace loom::mpm {

void declare_emitter_inputs(NodeSpec& s) {
  s.input<MpmState>("particles", "particles to add these to (same dimension)").optional()
      .input<int>("dimension", 2, "2 or 3 (ignored when `particles` is linked)").range(2, 3)
      .enum_input("material", Material::elastic,
                  {{Material::fluid, "fluid"},
                   {Material::elastic, "elastic"},
                   {Material::snow, "snow"},
                   {Material::sand, "sand"}},
                  "fluid: J-based pressure; elastic: fixed corotated; snow: Stomakhin 2013; "
                  "sand: Drucker-Prager (Klár 2016)")
      .input<double>("E", 1e4, "Young's modulus (fluid: the bulk modulus)").at_least(0)
      .input<double>("nu", 0.2, "Poisson's ratio (unused by fluid)").range(-0.99, 0.49)
      .input<double>("density", 1.0, "mass per unit volume (per unit area in 2D)").at_least(0)
      .input<Vec3>("velocity", Vec3(0, 0, 0), "initial velocity (z unused in 2D)")
      .input<Color>("color", Color{Eigen::Vector4d(0.9, 0.9, 0.9, 1)}, "linear RGB colour")
      .enum_input("sampling", Sampling::jittered,
                  {{Sampling::grid, "grid"},
                   {Sampling::jittered, "jittered"},
                   {Sampling::poisson, "poisson"},
                   {Sampling::random, "random"}},
                  "particle placement: a regular or jittered lattice, Poisson-disk, or "
                  "`count` uniform random points (mpm88)")
      .input<double>("spacing", 1.0 / 256, "distance between particles (grid, jittered, poisson)")
      .at_least(1e-6)
      .input<int>("count", 8192, "number of particles (random sampling)").range(1, 100'000'000)
      .input<double>("particle_volume", 0.0,
                     "volume (area in 2D) per particle; 0: the shape's volume / count")
      .at_least(0);
}

EmitOptions read_emit_options(Inputs& in, Context& ctx) {
  EmitOptions o;
  o.material = in.get<Material>("material");
  o.E = in.get<double>("E");
  o.nu = in.get<double>("nu");
  o.density = in.get<double>("density");
  o.velocity = in.get<Vec3>("velocity");
  o.color = in.get<Color>("color").rgba.head<3>().cast<float>();
  o.sampling = in.get<Sampling>("sampling");
  o.spacing = in.get<double>("spacing");
  o.count = in.get<int>("count");
  o.particle_volume = in.get<double>("particle_volume");
  o.seed = ctx.seed();
  o.progress = [&ctx](double done, double total) {
    ctx.progress(done, total, "placing particles");
    ctx.check_cancelled();
  };
  o.check_cancelled = [&ctx] { ctx.check_cancelled(); };
  return o;
}

int read_dimension(Inputs& in) {
  if (in.has("particles")) return in.get<MpmState>("particles").dim;
  return in.get<int>("dimension");
}

MpmState append_particles(Inputs& in, int dim, Particles<2>&& added2, Particles<3>&& added3) {
  MpmState state;
  if (in.has("particles")) state = in.get<MpmState>("particles");
  state.dim = dim;
  if (dim == 2) {
    if (state.p2.size() == 0) state.p2 = std::move(added2);
    else state.p2.append(added2);
  } else {
    if (state.p3.size() == 0) state.p3 = std::move(added3);
    else state.p3.append(added3);
  }
  return state;
}

}  // namespace loom::mpm
