// Tiles of an image split over MPI ranks (PixelRegion's parts), seen from MPI:
// the datatype of a part's tiles in the image's own memory, the pixels a part
// may be gathered into, a part's tiles copied between images.
#pragma once

#include <mpi.h>

#include "loom/image.hpp"
#include "loom/value.hpp"

namespace loom::runner {

// The tiles of part `part` of `parts` in rows [y0, y1) of `image`, as one MPI
// datatype over the image's own memory, so tiles are sent from and received
// into the image with no packed copy (PixelRegion's tiles: tile t at column
// t % columns of its band of rows). In a band, the part's tiles are every
// parts-th column from its first: one strided vector of whole tiles, plus the
// band's last tile on its own when the image's width cuts it short. Built from
// bytes (a pixel is elemSize() of them), so any channel count or depth fits.
MPI_Datatype tiles_type(const cv::Mat& image, int y0, int y1, int tile, int part, int parts);

// The pixels to receive the other ranks' tiles into (or to keep this rank's
// dealt parts in): the part's own when nothing else holds them (the node made
// them for this output), so the image is gathered in place; else a copy (a
// node may output pixels it shares with an input, which a cache holds, or
// with another output).
cv::Mat writable_pixels(const Value& part);

// Copies the tiles of part `part` of `parts` from one image to another.
void copy_part(const cv::Mat& from, cv::Mat& to, int tile, int part, int parts);

}  // namespace loom::runner
