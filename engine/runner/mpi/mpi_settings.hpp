// What `loom run --mpi-split/--mpi-tile` asked (mpi_launch.cpp reads them).
#pragma once

#include <string>

namespace loom::runner {

struct MpiSettings {
  std::string split = "auto";  // auto, frames, tiles, samples
  int tile = 32;               // tile edge in pixels (PixelRegion::tile)
  std::string deal = "static";  // static, dynamic: how frames, points, tiles are dealt
};
MpiSettings& mpi_settings();

}  // namespace loom::runner
