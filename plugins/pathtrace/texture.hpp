// Texture lookups at a hit's UVs: repeat wrap, v = 0 the image's bottom row
// (OBJ / OpenGL, as Render samples them). Channels beyond the image's are
// its first channel repeated; non-finite or negative texels read as 0 only
// where a color is expected (texel_color).
#pragma once

#include "loom/image.hpp"
#include "sampling.hpp"

namespace loom::pathtrace {

// Nearest texel, clamped to non-negative finite values (base colour maps).
Vec3f texel_color(const Image& image, const Vec2f& uv);
// Bilinear between the four nearest texel centres, raw values (normal and
// displacement maps; the maps are checked finite before rendering).
Vec3f texel_bilinear(const Image& image, const Vec2f& uv);

}  // namespace loom::pathtrace
