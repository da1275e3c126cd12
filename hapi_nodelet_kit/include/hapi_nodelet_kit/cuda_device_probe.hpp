// Whether a CUDA device is usable, with its name or why not: the one probe
// behind the packages' GPU tests (skip without a device), benchmarks and
// CPU/GPU selection. Header-only; include it only from code compiled
// against the CUDA runtime (a package's src/cuda).
#pragma once

#include <cuda_runtime.h>

#include <string>

namespace hapi_nodelet_kit {

// *info (may be null): "<name> (sm_XY)", or why there is no device.
inline bool cudaDeviceUsable(std::string* info) {
  int n = 0;
  const cudaError_t e = cudaGetDeviceCount(&n);
  if (e != cudaSuccess) {
    if (info) *info = std::string("no usable CUDA runtime/driver: ") + cudaGetErrorString(e);
    cudaGetLastError();  // clear the error so that later calls start clean
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

}  // namespace hapi_nodelet_kit
