// Minimal owning device allocation (no CUDA code runs in constructors, so
// allocation failures surface as a status, never as an exception).
#pragma once

#include <cuda_runtime.h>

#include <cstddef>
#include <utility>

namespace hapi_eskf {
namespace cuda {

template <typename T>
class DeviceBuffer {
 public:
  DeviceBuffer() = default;
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;
  ~DeviceBuffer() { release(); }

  // Grows (never shrinks) to at least `count` elements; contents are lost on growth.
  cudaError_t ensure(std::size_t count) {
    if (count <= count_) return cudaSuccess;
    release();
    void* p = nullptr;
    const cudaError_t e = cudaMalloc(&p, count * sizeof(T));
    if (e != cudaSuccess) return e;
    ptr_ = static_cast<T*>(p);
    count_ = count;
    return cudaSuccess;
  }
  void release() {
    if (ptr_ != nullptr) cudaFree(ptr_);
    ptr_ = nullptr;
    count_ = 0;
  }
  void swap(DeviceBuffer& o) {
    std::swap(ptr_, o.ptr_);
    std::swap(count_, o.count_);
  }
  T* get() const { return ptr_; }
  std::size_t count() const { return count_; }
  std::size_t bytes() const { return count_ * sizeof(T); }

 private:
  T* ptr_ = nullptr;
  std::size_t count_ = 0;
};

}  // namespace cuda
}  // namespace hapi_eskf
