#include "hapi_surface/cuda/tsdf_cuda.hpp"

#include "device_buffer.cuh"
#include "tsdf_launch.hpp"

#include <cuda_runtime.h>
#include <hapi_nodelet_kit/cuda_device_probe.hpp>

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

struct CudaTsdfIntegrator::Buffers {
  DeviceFloats depth, weight, tsdf, voxel_weight;
  cudaEvent_t start = nullptr, kernel_start = nullptr, kernel_end = nullptr, end = nullptr;
  Buffers() {
    cudaEventCreate(&start);
    cudaEventCreate(&kernel_start);
    cudaEventCreate(&kernel_end);
    cudaEventCreate(&end);
  }
  ~Buffers() {
    cudaEventDestroy(start);
    cudaEventDestroy(kernel_start);
    cudaEventDestroy(kernel_end);
    cudaEventDestroy(end);
  }
};

bool surfaceCudaAvailable(std::string* info) { return hapi_nodelet_kit::cudaDeviceUsable(info); }

CudaTsdfIntegrator::CudaTsdfIntegrator() : buf_(std::make_unique<Buffers>()) {}
CudaTsdfIntegrator::~CudaTsdfIntegrator() = default;

SurfaceStatus CudaTsdfIntegrator::integrate(TsdfVolume* volume, const DepthFrame& frame) {
  const SurfaceStatus st = checkDepthFrame(frame, volume->settings());
  if (st != SurfaceStatus::kOk) return st;
  const VoxelGrid& g = volume->grid();
  const TsdfIntegrationParams p = integrationParams(g, frame, volume->settings());
  const std::size_t nv = g.size(), np = frame.depth.data.size();
  const bool has_weight = !frame.weight.empty();
  Buffers& b = *buf_;
  if (!b.depth.reserve(np) || (has_weight && !b.weight.reserve(np)) || !b.tsdf.reserve(nv) ||
      !b.voxel_weight.reserve(nv)) {
    cudaGetLastError();
    return SurfaceStatus::kDeviceError;
  }
  const std::size_t vbytes = nv * sizeof(float), pbytes = np * sizeof(float);
  bool ok = cudaEventRecord(b.start) == cudaSuccess;
  ok = ok && cudaMemcpy(b.depth.ptr, frame.depth.data.data(), pbytes, cudaMemcpyHostToDevice) == cudaSuccess;
  ok = ok && (!has_weight ||
              cudaMemcpy(b.weight.ptr, frame.weight.data.data(), pbytes, cudaMemcpyHostToDevice) == cudaSuccess);
  ok = ok && cudaMemcpy(b.tsdf.ptr, volume->tsdf().data(), vbytes, cudaMemcpyHostToDevice) == cudaSuccess;
  ok = ok && cudaMemcpy(b.voxel_weight.ptr, volume->weight().data(), vbytes, cudaMemcpyHostToDevice) == cudaSuccess;
  if (ok) {
    cudaEventRecord(b.kernel_start);
    ok = launchIntegrate(p, b.depth.ptr, has_weight ? b.weight.ptr : nullptr, b.tsdf.ptr, b.voxel_weight.ptr);
    cudaEventRecord(b.kernel_end);
  }
  // Download into copies first: the host volume changes only on success.
  std::vector<float> tsdf(nv), weight(nv);
  ok = ok && cudaMemcpy(tsdf.data(), b.tsdf.ptr, vbytes, cudaMemcpyDeviceToHost) == cudaSuccess;
  ok = ok && cudaMemcpy(weight.data(), b.voxel_weight.ptr, vbytes, cudaMemcpyDeviceToHost) == cudaSuccess;
  ok = ok && cudaEventRecord(b.end) == cudaSuccess && cudaEventSynchronize(b.end) == cudaSuccess;
  if (!ok) {
    cudaGetLastError();
    return SurfaceStatus::kDeviceError;
  }
  cudaEventElapsedTime(&kernel_ms_, b.kernel_start, b.kernel_end);
  cudaEventElapsedTime(&total_ms_, b.start, b.end);
  volume->mutableTsdf().swap(tsdf);
  volume->mutableWeight().swap(weight);
  return SurfaceStatus::kOk;
}

}  // namespace hapi_surface
