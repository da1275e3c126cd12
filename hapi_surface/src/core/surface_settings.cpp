#include "hapi_surface/surface_settings.hpp"

#include <cmath>

namespace hapi_surface {

std::string SurfaceSettings::validate() const {
  std::string e;
  forEachField(*this, [&](const FieldInfo& f, const auto& v) {
    if (e.empty()) e = rangeError(f, v);
  });
  if (!e.empty()) return e;
  if (max_depth <= min_depth) return "max_depth must be > min_depth";
  if (truncation < voxel_size) return "truncation must be >= voxel_size (the zero crossing needs two samples)";
  const double voxels = std::ceil(volume_size_x / voxel_size) * std::ceil(volume_size_y / voxel_size) *
                        std::ceil(volume_size_z / voxel_size);
  if (voxels > max_voxels) return "the volume has more than max_voxels voxels: larger voxel_size or a smaller volume";
  return "";
}

}  // namespace hapi_surface
