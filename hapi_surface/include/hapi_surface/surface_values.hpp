// The imaging camera's values on the surface (docs/DESIGN.md "Surface",
// eq. S4-S5). Values are accumulated per voxel of the TSDF grid, at the ends
// of the mesh's vertex edges, so they survive re-meshing: a weighted mean
// per voxel, a vertex's value the mean of its edge's two ends.
#pragma once

#include "hapi_surface/float_image.hpp"
#include "hapi_surface/mesh.hpp"
#include "hapi_surface/pinhole_camera.hpp"
#include "hapi_surface/tsdf_volume.hpp"

#include <Eigen/Geometry>

#include <cstddef>
#include <vector>

namespace hapi_surface {

struct ProjectionResult {
  SurfaceStatus status = SurfaceStatus::kOk;
  std::size_t voxels_updated = 0;   // voxels at the mesh's vertex edges that received a value
  std::size_t voxels_occluded = 0;  // in the image but behind the rendered mesh
};

class SurfaceValues {
 public:
  explicit SurfaceValues(std::size_t voxels = 0);

  // Adds one imaging frame (`image` already float, NaN = no value) seen by
  // `camera` at `T_world_camera`, with `mesh` (extracted from `volume`) for
  // the occlusion test. Errors (bad camera or pose, image size not the
  // camera's, volume size not this object's, empty mesh) change nothing.
  ProjectionResult addFrame(const TsdfVolume& volume, const Mesh& mesh, const FloatImage& image,
                            const PinholeCamera& camera, const Eigen::Isometry3d& T_world_camera);

  // Fills mesh->values / value_weights from the voxels of its vertices' edges.
  void sampleVertices(Mesh* mesh) const;

  void clear();
  std::size_t size() const { return sum_w_.size(); }

 private:
  std::vector<float> sum_w_, sum_wv_;
};

}  // namespace hapi_surface
