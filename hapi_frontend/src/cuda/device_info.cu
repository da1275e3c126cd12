// Device presence probe used by tests (GTEST_SKIP), benchmarks and the
// pipeline's backend selection.
#include "hapi_frontend/cuda/orb_cuda.hpp"

#include <cuda_runtime.h>

namespace hapi_frontend {

bool cudaDeviceAvailable(std::string* info) {
  int n = 0;
  const cudaError_t e = cudaGetDeviceCount(&n);
  if (e != cudaSuccess) {
    if (info) *info = std::string("no usable CUDA runtime/driver: ") + cudaGetErrorString(e);
    cudaGetLastError();  // clear the sticky-free error so later calls start clean
    return false;
  }
  if (n <= 0) {
    if (info) *info = "no CUDA device";
    return false;
  }
  cudaDeviceProp prop;
  if (cudaGetDeviceProperties(&prop, 0) != cudaSuccess) {
    if (info) *info = "cudaGetDeviceProperties failed";
    cudaGetLastError();
    return false;
  }
  if (info) *info = std::string(prop.name) + " (sm_" + std::to_string(prop.major) + std::to_string(prop.minor) + ")";
  return true;
}

}  // namespace hapi_frontend
