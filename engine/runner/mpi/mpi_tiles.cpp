// Tiles of an image split over MPI ranks (mpi_tiles.hpp).
#include "mpi/mpi_tiles.hpp"

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

namespace loom::runner {

MPI_Datatype tiles_type(const cv::Mat& image, int y0, int y1, int tile, int part, int parts) {
  const int columns = (image.cols + tile - 1) / tile, whole_columns = image.cols / tile;
  const MPI_Aint row = MPI_Aint(image.step), pixel = MPI_Aint(image.elemSize());
  std::vector<MPI_Datatype> types;
  std::vector<MPI_Aint> at;
  auto add = [&](int y, int h, int column, int count, int width) {
    MPI_Datatype one, strided;  // one tile: h rows of width pixels; then `count` of them, `parts` columns apart
    MPI_Type_create_hvector(h, int(width * pixel), row, MPI_BYTE, &one);
    MPI_Type_create_hvector(count, 1, MPI_Aint(parts) * tile * pixel, one, &strided);
    MPI_Type_free(&one);
    types.push_back(strided);
    at.push_back(MPI_Aint(y) * row + MPI_Aint(column) * tile * pixel);
  };
  for (int band = y0 / tile; band * tile < y1; ++band) {
    const int y = std::max(y0, band * tile), h = std::min(y1, (band + 1) * tile) - y;
    const int first = ((part - int(std::int64_t(band) * columns % parts)) % parts + parts) % parts;
    if (first < whole_columns) add(y, h, first, (whole_columns - 1 - first) / parts + 1, tile);
    const int last = columns - 1;
    if (whole_columns < columns && last >= first && (last - first) % parts == 0)
      add(y, h, last, 1, image.cols - last * tile);
  }
  MPI_Datatype tiles;
  const std::vector<int> ones(types.size(), 1);
  MPI_Type_create_struct(int(types.size()), ones.data(), at.data(), types.data(), &tiles);
  MPI_Type_commit(&tiles);
  for (MPI_Datatype& t : types) MPI_Type_free(&t);
  return tiles;
}

cv::Mat writable_pixels(const Value& part) {
  const std::shared_ptr<const Image> image = part.shared<Image>();
  const cv::Mat& pixels = image->pixels;
  const bool alone = image.use_count() == 2 && pixels.u && pixels.u->refcount == 1;  // `part` and `image`
  return alone ? pixels : pixels.clone();
}

void copy_part(const cv::Mat& from, cv::Mat& to, int tile, int part, int parts) {
  const int columns = (from.cols + tile - 1) / tile, rows = (from.rows + tile - 1) / tile;
  for (std::int64_t t = part; t < std::int64_t(columns) * rows; t += parts) {
    const int x = int(t % columns) * tile, y = int(t / columns) * tile;
    const cv::Rect r(x, y, std::min(tile, from.cols - x), std::min(tile, from.rows - y));
    from(r).copyTo(to(r));
  }
}

}  // namespace loom::runner
