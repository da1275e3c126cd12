#include "hapi_surface/cuda/tsdf_cuda.hpp"

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

__global__ void activeCellsKernel(const float* tsdf, const float* weight, int nx, int ny, int nz, CubeOffsets off,
                                  float min_weight, std::uint8_t* active) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  const int j = blockIdx.y * blockDim.y + threadIdx.y;
  const int k = blockIdx.z;
  if (i >= nx || j >= ny) return;
  const unsigned int g = (static_cast<unsigned int>(k) * ny + j) * static_cast<unsigned int>(nx) + i;
  active[g] = i + 1 < nx && j + 1 < ny && k + 1 < nz && cubeActive(tsdf, weight, g, off, min_weight) ? 1 : 0;
}

// A device buffer that grows to the largest size asked for.
template <typename T>
struct DeviceBuffer {
  T* ptr = nullptr;
  std::size_t n = 0;
  ~DeviceBuffer() { cudaFree(ptr); }
  bool reserve(std::size_t want) {
    if (want <= n) return true;
    cudaFree(ptr);
    ptr = nullptr;
    n = 0;
    if (cudaMalloc(&ptr, want * sizeof(T)) != cudaSuccess) return false;
    n = want;
    return true;
  }
};
using DeviceFloats = DeviceBuffer<float>;

}  // namespace

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
    const dim3 block(32, 8, 1);
    const dim3 grid((g.dims.x() + 31) / 32, (g.dims.y() + 7) / 8, g.dims.z());
    cudaEventRecord(b.kernel_start);
    integrateKernel<<<grid, block>>>(p, b.depth.ptr, has_weight ? b.weight.ptr : nullptr, b.tsdf.ptr,
                                     b.voxel_weight.ptr);
    cudaEventRecord(b.kernel_end);
    ok = cudaGetLastError() == cudaSuccess;
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

struct CudaActiveCells::Buffers {
  DeviceFloats tsdf, weight;
  DeviceBuffer<std::uint8_t> active;
  cudaEvent_t start = nullptr, end = nullptr;
  Buffers() {
    cudaEventCreate(&start);
    cudaEventCreate(&end);
  }
  ~Buffers() {
    cudaEventDestroy(start);
    cudaEventDestroy(end);
  }
};

CudaActiveCells::CudaActiveCells() : buf_(std::make_unique<Buffers>()) {}
CudaActiveCells::~CudaActiveCells() = default;

SurfaceStatus CudaActiveCells::find(const TsdfVolume& volume, std::vector<std::uint8_t>* active) {
  const VoxelGrid& g = volume.grid();
  const std::size_t nv = g.size(), bytes = nv * sizeof(float);
  Buffers& b = *buf_;
  if (!b.tsdf.reserve(nv) || !b.weight.reserve(nv) || !b.active.reserve(nv)) {
    cudaGetLastError();
    return SurfaceStatus::kDeviceError;
  }
  bool ok = cudaEventRecord(b.start) == cudaSuccess;
  ok = ok && cudaMemcpy(b.tsdf.ptr, volume.tsdf().data(), bytes, cudaMemcpyHostToDevice) == cudaSuccess;
  ok = ok && cudaMemcpy(b.weight.ptr, volume.weight().data(), bytes, cudaMemcpyHostToDevice) == cudaSuccess;
  if (ok) {
    const dim3 block(32, 8, 1);
    const dim3 grid((g.dims.x() + 31) / 32, (g.dims.y() + 7) / 8, g.dims.z());
    activeCellsKernel<<<grid, block>>>(
        b.tsdf.ptr, b.weight.ptr, g.dims.x(), g.dims.y(), g.dims.z(),
        cubeOffsets(static_cast<unsigned int>(g.dims.x()), static_cast<unsigned int>(g.dims.y())),
        static_cast<float>(volume.settings().mesh_min_weight), b.active.ptr);
    ok = cudaGetLastError() == cudaSuccess;
  }
  std::vector<std::uint8_t> out(nv);
  ok = ok && cudaMemcpy(out.data(), b.active.ptr, nv, cudaMemcpyDeviceToHost) == cudaSuccess;
  ok = ok && cudaEventRecord(b.end) == cudaSuccess && cudaEventSynchronize(b.end) == cudaSuccess;
  if (!ok) {
    cudaGetLastError();
    return SurfaceStatus::kDeviceError;
  }
  cudaEventElapsedTime(&total_ms_, b.start, b.end);
  active->swap(out);
  return SurfaceStatus::kOk;
}

}  // namespace hapi_surface
