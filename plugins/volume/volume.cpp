#include "volume.hpp"

#include <sstream>

std::string loom::TypeTraits<loom::volume::Volume>::summary(const loom::volume::Volume& v) {
  std::ostringstream s;
  s << "Volume voxel " << v.voxel_size << ", " << (v.density ? v.density->activeVoxelCount() : 0) << " voxels"
    << (v.velocity ? ", density and velocity" : ", density");
  return s.str();
}
