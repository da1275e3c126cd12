// The block matcher on the device (cuda/dense_depth_cuda.hpp): one thread
// per left pixel, the per-pixel rule shared with the CPU reference.
#include "hapi_surface/cuda/dense_depth_cuda.hpp"

#include <cuda_runtime.h>

#include <stdexcept>
#include <string>

namespace hapi_surface {
namespace {

void check(cudaError_t e, const char* what) {
  if (e != cudaSuccess) throw std::runtime_error(std::string("CUDA error in ") + what + ": " + cudaGetErrorString(e));
}

__global__ void blockMatchKernel(const std::uint8_t* l, const std::uint8_t* r, int w, int h, int stride,
                                 BlockMatchParams p, float* out) {
  const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
  if (x >= w || y >= h) return;
  out[static_cast<std::int64_t>(y) * w + x] = block_match_detail::matchPixel(l, r, w, h, stride, x, y, p);
}

// Device memory freed on every path out.
struct DeviceBytes {
  void* ptr = nullptr;
  explicit DeviceBytes(std::size_t n) { check(cudaMalloc(&ptr, n), "cudaMalloc"); }
  ~DeviceBytes() { cudaFree(ptr); }
  DeviceBytes(const DeviceBytes&) = delete;
  DeviceBytes& operator=(const DeviceBytes&) = delete;
};

}  // namespace

bool denseDepthCudaDevice() {
  int n = 0;
  return cudaGetDeviceCount(&n) == cudaSuccess && n > 0;
}

void blockMatchCuda(const std::uint8_t* left, const std::uint8_t* right, int w, int h, int stride,
                    const BlockMatchParams& p, float* disparity) {
  const std::size_t image = static_cast<std::size_t>(stride) * h, out = static_cast<std::size_t>(w) * h * sizeof(float);
  DeviceBytes dl(image), dr(image), dd(out);
  check(cudaMemcpy(dl.ptr, left, image, cudaMemcpyHostToDevice), "cudaMemcpy left");
  check(cudaMemcpy(dr.ptr, right, image, cudaMemcpyHostToDevice), "cudaMemcpy right");
  const dim3 block(16, 8), grid((w + 15) / 16, (h + 7) / 8);
  blockMatchKernel<<<grid, block>>>(static_cast<const std::uint8_t*>(dl.ptr), static_cast<const std::uint8_t*>(dr.ptr),
                                    w, h, stride, p, static_cast<float*>(dd.ptr));
  check(cudaGetLastError(), "blockMatchKernel launch");
  check(cudaMemcpy(disparity, dd.ptr, out, cudaMemcpyDeviceToHost), "cudaMemcpy disparity");
}

}  // namespace hapi_surface
