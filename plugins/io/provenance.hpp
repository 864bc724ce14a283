// What every file the io plugin writes says about where it came from, in its
// header: the node (its id, as a path inside groups), its seed and the frame.
// Not the graph's file: a file's bytes must not depend on the driver that ran
// the graph (decision 19), and `loom submit` runs a copy of the graph in its
// job folder while Python's Session has no file at all. `loom info FILE`
// prints them back.
#pragma once

#include <string>

#include "image_codec.hpp"
#include "loom/plugin.hpp"

namespace loom::io {

inline Metadata provenance(const Context& ctx) {
  const std::string node = ctx.node_id(), seed = std::to_string(ctx.seed()), frame = std::to_string(ctx.time().frame);
  // ImageDescription is the one attribute PNG, TIFF, JPEG and EXR all keep;
  // the loom: attributes are for tools that list attributes (EXR, PNG).
  return {{"loom:node", node},
          {"loom:seed", seed},
          {"loom:frame", frame},
          {"ImageDescription", "Loom: node " + node + ", seed " + seed + ", frame " + frame}};
}

}  // namespace loom::io
