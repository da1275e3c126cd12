// The zero level set of a TSDF volume as a triangle mesh (docs/DESIGN.md
// "Surface"): marching tetrahedra on the Kuhn split of each cube (6
// tetrahedra along its main diagonal), which has no ambiguous case, so the
// mesh has no cracks, and needs no 256-case table. Vertices on a grid edge
// are shared by every triangle touching that edge; normals are the
// normalised TSDF gradient (central differences, interpolated along the
// edge), and each triangle is wound counter-clockwise seen from that side.
// Only cubes whose 8 corners all have weight >= mesh_min_weight take part
// (cubeActive(), tsdf_math.hpp).
#pragma once

#include "hapi_surface/mesh.hpp"
#include "hapi_surface/tsdf_volume.hpp"

#include <cstdint>
#include <vector>

namespace hapi_surface {

// The CUDA mesher (CudaSurfaceVolume::extractMesh) gives the same mesh.
Mesh extractMesh(const TsdfVolume& volume);

}  // namespace hapi_surface
