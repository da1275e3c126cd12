// The depth (z along the optical axis) of a mesh seen by a pinhole camera,
// a z-buffer: the occlusion test of the projection (docs/DESIGN.md
// "Surface", eq. S4). Triangles are rasterised at pixel centres with depth
// interpolated perspective-correctly (1/z is affine in the image).
#pragma once

#include "hapi_surface/float_image.hpp"
#include "hapi_surface/mesh.hpp"
#include "hapi_surface/pinhole_camera.hpp"

#include <Eigen/Geometry>

namespace hapi_surface {

// +inf where no triangle is seen. Triangles with a vertex behind the camera
// (z <= 1 mm) are skipped.
FloatImage renderMeshDepth(const Mesh& mesh, const PinholeCamera& camera, const Eigen::Isometry3d& T_world_camera);

}  // namespace hapi_surface
