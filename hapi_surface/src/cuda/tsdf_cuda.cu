// The TSDF integration kernel (tsdf_launch.hpp): updateVoxel()
// (tsdf_math.hpp), one thread per voxel.
#include "tsdf_launch.hpp"

#include <cuda_runtime.h>

#include <cstddef>

namespace hapi_surface {
namespace {

__global__ void integrateKernel(TsdfIntegrationParams p, const float* depth, const float* weight, float* tsdf,
                                float* voxel_weight) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  const int j = blockIdx.y * blockDim.y + threadIdx.y;
  const int k = blockIdx.z;
  if (i >= p.dims[0] || j >= p.dims[1]) return;
  const std::size_t idx = (static_cast<std::size_t>(k) * p.dims[1] + j) * static_cast<std::size_t>(p.dims[0]) + i;
  updateVoxel(p, i, j, k, depth, weight, &tsdf[idx], &voxel_weight[idx]);
}

}  // namespace

bool launchIntegrate(const TsdfIntegrationParams& p, const float* depth, const float* weight, float* tsdf,
                     float* voxel_weight) {
  const dim3 block(32, 8, 1);
  const dim3 grid((p.dims[0] + 31) / 32, (p.dims[1] + 7) / 8, p.dims[2]);
  integrateKernel<<<grid, block>>>(p, depth, weight, tsdf, voxel_weight);
  return cudaGetLastError() == cudaSuccess;
}

}  // namespace hapi_surface
