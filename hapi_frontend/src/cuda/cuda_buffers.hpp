// Internal: minimal RAII owners for device and pinned host allocations, so
// buffers are reused across frames and released on every exit path.
#pragma once

#include "cuda_check.hpp"

#include <cstddef>
#include <utility>

namespace hapi_frontend {
namespace cuda_detail {

template <typename T>
class DeviceBuffer {
 public:
  DeviceBuffer() = default;
  ~DeviceBuffer() { release(); }
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;
  // Grows only: a smaller request keeps the allocation (frames of one stream
  // usually have one size).
  void reserve(std::size_t n) {
    if (n <= cap_) return;
    release();
    HAPI_CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&p_), n * sizeof(T)));
    cap_ = n;
  }
  T* get() const { return p_; }
  std::size_t capacity() const { return cap_; }
  void release() {
    if (p_) cudaFree(p_);  // no throw from destructors
    p_ = nullptr;
    cap_ = 0;
  }

 private:
  T* p_ = nullptr;
  std::size_t cap_ = 0;
};

// Page-locked host memory: required for truly asynchronous copies.
template <typename T>
class PinnedBuffer {
 public:
  PinnedBuffer() = default;
  ~PinnedBuffer() { release(); }
  PinnedBuffer(const PinnedBuffer&) = delete;
  PinnedBuffer& operator=(const PinnedBuffer&) = delete;
  void reserve(std::size_t n) {
    if (n <= cap_) return;
    release();
    HAPI_CUDA_CHECK(cudaMallocHost(reinterpret_cast<void**>(&p_), n * sizeof(T)));
    cap_ = n;
  }
  T* get() const { return p_; }
  std::size_t capacity() const { return cap_; }
  void release() {
    if (p_) cudaFreeHost(p_);
    p_ = nullptr;
    cap_ = 0;
  }

 private:
  T* p_ = nullptr;
  std::size_t cap_ = 0;
};

}  // namespace cuda_detail
}  // namespace hapi_frontend
