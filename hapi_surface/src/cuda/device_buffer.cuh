// A device buffer that grows to the largest size asked for (the CUDA
// surface code's one allocation rule).
#pragma once

#include <cuda_runtime.h>

#include <cstddef>

namespace hapi_surface {

template <typename T>
struct DeviceBuffer {
  T* ptr = nullptr;
  std::size_t n = 0;
  DeviceBuffer() = default;
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;
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

}  // namespace hapi_surface
