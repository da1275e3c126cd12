// The per-voxel TSDF update (docs/DESIGN.md "Surface", eq. S1-S3) and the
// test of a cube that takes part in the mesh ("Mesh"), written once for the
// CPU and the CUDA kernels. Single precision, no fused
// multiply-add (-ffp-contract=off / --fmad=false): both give the same bits.
#pragma once

#ifdef __CUDACC__
#define HAPI_SURFACE_HD __host__ __device__ __forceinline__
#else
#define HAPI_SURFACE_HD inline
#endif

#include <math.h>

namespace hapi_surface {

// Everything the update of one voxel needs, as plain floats (copied to the
// GPU as is). T_cw: the world -> camera transform, row-major 3 x 4.
struct TsdfIntegrationParams {
  float origin[3];  // world position of voxel (0,0,0)'s corner
  float voxel;      // voxel edge (m)
  int dims[3];      // voxels along x, y, z
  float T_cw[12];
  float fx, fy, cx, cy;
  int width, height;  // depth image size
  float truncation, max_weight, min_depth, max_depth;
};

// The voxel (i, j, k)'s new (tsdf, weight) from the depth image (and an
// optional per-pixel weight, nullptr = 1). Unchanged when its centre lies
// behind the camera, outside the image, on a pixel without valid depth or
// weight, or more than `truncation` behind the measured surface.
HAPI_SURFACE_HD void updateVoxel(const TsdfIntegrationParams& p, int i, int j, int k, const float* depth,
                                 const float* weight, float* tsdf, float* voxel_weight) {
  // Voxel centre in the world, then in the camera (S1).
  const float xw = p.origin[0] + (static_cast<float>(i) + 0.5f) * p.voxel;
  const float yw = p.origin[1] + (static_cast<float>(j) + 0.5f) * p.voxel;
  const float zw = p.origin[2] + (static_cast<float>(k) + 0.5f) * p.voxel;
  const float* T = p.T_cw;
  const float xc = T[0] * xw + T[1] * yw + T[2] * zw + T[3];
  const float yc = T[4] * xw + T[5] * yw + T[6] * zw + T[7];
  const float zc = T[8] * xw + T[9] * yw + T[10] * zw + T[11];
  if (!(zc > 0.f)) return;
  // The nearest pixel (pixel centres at integer coordinates, REP-104).
  const float u = p.fx * (xc / zc) + p.cx + 0.5f;
  const float v = p.fy * (yc / zc) + p.cy + 0.5f;
  if (!(u >= 0.f && v >= 0.f)) return;  // also NaN
  const int pu = static_cast<int>(u), pv = static_cast<int>(v);
  if (pu >= p.width || pv >= p.height) return;
  const int idx = pv * p.width + pu;
  const float d = depth[idx];
  if (!(d >= p.min_depth && d <= p.max_depth)) return;  // NaN, inf, out of range
  const float w = weight ? weight[idx] : 1.f;
  if (!(w > 0.f) || !(w < 3.0e38f)) return;
  // Projective signed distance along the optical axis (S2).
  const float sdf = d - zc;
  if (sdf < -p.truncation) return;  // hidden behind the measured surface
  const float f = sdf >= p.truncation ? 1.f : sdf / p.truncation;
  // Weighted running average, weight capped (S3).
  const float W = *voxel_weight;
  *tsdf = (*tsdf * W + f * w) / (W + w);
  const float Wn = W + w;
  *voxel_weight = Wn < p.max_weight ? Wn : p.max_weight;
}

// Linear offsets of a cube's 8 corners from its corner 0 in a grid of nx x
// ny x . voxels, corners in the order (0,0,0), (1,0,0), (1,1,0), (0,1,0),
// (0,0,1), (1,0,1), (1,1,1), (0,1,1).
struct CubeOffsets {
  unsigned int o[8];
};

HAPI_SURFACE_HD CubeOffsets cubeOffsets(unsigned int nx, unsigned int ny) {
  const unsigned int s = nx * ny;
  return CubeOffsets{{0u, 1u, 1u + nx, nx, s, 1u + s, 1u + nx + s, nx + s}};
}

// Whether the cube at corner-0 voxel g is meshed: all 8 corners have weight
// >= min_weight and the TSDF changes sign among them.
HAPI_SURFACE_HD bool cubeActive(const float* tsdf, const float* weight, unsigned int g, const CubeOffsets& c,
                                float min_weight) {
  bool any_in = false, any_out = false;
  for (int k = 0; k < 8; ++k) {
    const unsigned int idx = g + c.o[k];
    if (weight[idx] < min_weight) return false;
    if (tsdf[idx] < 0.f) any_in = true;
    else any_out = true;
  }
  return any_in && any_out;
}

}  // namespace hapi_surface
