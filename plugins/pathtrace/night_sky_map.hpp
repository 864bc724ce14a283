// A procedural night sky as a lat-long radiance map (loom::latlong_uv's
// convention): a dark blue gradient above the horizon, a dim ground, a few
// hundred stars and a moon disk carrying most of the light. An environment
// map made in a graph, so the environment scenes need no files.
#pragma once

#include <cstdint>

#include "loom/image.hpp"

namespace loom::pathtrace {

struct NightSkyOptions {
  int width = 512, height = 256;
  double moon_elevation = 0.5;  // radians above the horizon
  double moon_azimuth = 0.6;    // radians, about +y, 0 looks down -z
  double moon_radius = 0.03;    // angular radius, radians
  double moon_radiance = 300;
  double sky_radiance = 0.03;   // scale of the sky's blue gradient (brightest at the horizon)
  int stars = 400;
  std::uint64_t seed = 1;
};

Image night_sky_map(const NightSkyOptions& options);

}  // namespace loom::pathtrace
