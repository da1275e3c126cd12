// Entry points of the CUDA backends (include/hapi_eskf/cuda/cuda_backend.hpp):
// device checks, the memory needed up front and the factory of the dense
// backend (dense_cuda_backend.hpp); the partitioned one is made in
// partitioned_cuda_backend.cpp.
#include "hapi_eskf/covariance/cuda_backend.hpp"

#include "dense_cuda_backend.hpp"

#include <string>

namespace hapi_eskf {
namespace cuda {

bool deviceAvailable(int device, std::string* info) {
  std::string dummy;
  std::string* out = info != nullptr ? info : &dummy;
  const std::string dev = "CUDA device " + std::to_string(device);
  int count = 0;
  const cudaError_t e = cudaGetDeviceCount(&count);
  if (e != cudaSuccess) {
    *out = dev + " unusable: no CUDA device (" + cudaGetErrorString(e) + ")";
    cudaGetLastError();  // clear the sticky-free error so later calls start clean
    return false;
  }
  if (device < 0 || device >= count) {
    *out = dev + " requested, " + std::to_string(count) + " present";
    return false;
  }
  cudaDeviceProp p{};
  if (cudaGetDeviceProperties(&p, device) != cudaSuccess) {
    *out = dev + " unusable: cudaGetDeviceProperties failed";
    return false;
  }
  *out = dev + ": " + p.name + ", " + std::to_string(p.totalGlobalMem >> 20) + " MiB, sm_" +
         std::to_string(p.major) + std::to_string(p.minor);
  return true;
}

std::size_t upFrontBytes(int capacity, int descriptor_length, int pose_dim, Precision precision) {
  const std::size_t scalar = precision == Precision::kFp32 ? sizeof(float) : sizeof(double);
  const std::size_t ld = paddedLd(stateDim(capacity, pose_dim));
  const std::size_t pool = static_cast<std::size_t>(std::max(capacity, 1)) * std::max(descriptor_length, 1);
  // As CudaBackend::init: C, work, dx, F and Q; the two descriptor pools.
  return scalar * (ld * ld + ld * initialWorkColumns(capacity) + ld + 2 * kMaxPoseDim * kMaxPoseDim) + 2 * pool;
}

namespace {
std::string mib(std::size_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB"; }

// "CUDA device N has F MiB free of T MiB" ("" when the query fails).
std::string memoryText(int device, std::size_t* free_bytes) {
  std::size_t free_b = 0, total_b = 0;
  if (cudaSetDevice(device) != cudaSuccess || cudaMemGetInfo(&free_b, &total_b) != cudaSuccess) {
    cudaGetLastError();
    return "";
  }
  if (free_bytes) *free_bytes = free_b;
  return "CUDA device " + std::to_string(device) + " has " + mib(free_b) + " free of " + mib(total_b);
}
}  // namespace

bool poolFits(int capacity, int descriptor_length, int pose_dim, const EskfSettings& s, std::string* why) {
  std::string dummy;
  std::string* out = why != nullptr ? why : &dummy;
  if (!deviceAvailable(s.cuda_device, out)) return false;
  std::size_t free_b = 0;
  const std::string memory = memoryText(s.cuda_device, &free_b);
  if (memory.empty()) {
    *out = "CUDA device " + std::to_string(s.cuda_device) + ": cudaMemGetInfo failed";
    return false;
  }
  const std::size_t need = upFrontBytes(capacity, descriptor_length, pose_dim, s.precision);
  *out = "a pool of " + std::to_string(capacity) + " landmarks (" + toString(s.precision) + ") needs " + mib(need) +
         " of device memory; " + memory;
  return need <= free_b;
}

std::unique_ptr<CovarianceBackend> makeCudaBackend(int capacity, int descriptor_length, int pose_dim,
                                                   const EskfSettings& s, std::string* error) {
  std::string dummy;
  std::string* err = error != nullptr ? error : &dummy;
  if (capacity < 0 || descriptor_length < 0) {
    *err = "CUDA backend: capacity and descriptor length must be >= 0";
    return nullptr;
  }
  // The pose blocks of the motion models (with the inertial model's
  // calibration rows), with or without the frame-error rows: the sizes
  // covariance_kernels.cu unrolls.
  // The scene motion's 6 rows have the frame error's size: the same sizes.
  bool model_dim = false;
  for (int m : {kCameraMotionDim, kGyroDim, kInertialDim, kInertialDim + kCalibTimeOffsetDim,
                kInertialDim + kCalibExtrinsicDim, kInertialDim + kCalibExtrinsicDim + kCalibTimeOffsetDim})
    model_dim |= pose_dim == m || pose_dim == m + kFrameErrorDim;
  if (!model_dim) {
    *err = "CUDA backend: pose block must have the rows of a motion model (" + std::to_string(kCameraMotionDim) +
           ", " + std::to_string(kGyroDim) + " or " + std::to_string(kInertialDim) + " + " +
           std::to_string(kCalibExtrinsicDim) + " and/or " + std::to_string(kCalibTimeOffsetDim) +
           " calibration rows, + " + std::to_string(kFrameErrorDim) + " with the frame error or the scene motion; at most " +
           std::to_string(kMaxCudaPoseDim) + "), got " + std::to_string(pose_dim);
    return nullptr;
  }
  std::string info;
  if (!deviceAvailable(s.cuda_device, &info)) {
    *err = info;
    return nullptr;
  }
  std::string fit;
  if (!poolFits(capacity, descriptor_length, pose_dim, s, &fit)) {
    *err = "CUDA backend does not fit: " + fit + " (lower max_landmarks, or precision fp32)";
    return nullptr;
  }
  std::string why;
  if (s.precision == Precision::kFp32) {
    auto b = std::make_unique<CudaBackend<float>>(capacity, descriptor_length, pose_dim, s);
    if (b->init(&why)) return b;
  } else {
    auto b = std::make_unique<CudaBackend<double>>(capacity, descriptor_length, pose_dim, s);
    if (b->init(&why)) return b;
  }
  *err = "CUDA backend (capacity " + std::to_string(capacity) + ") on " + info + ": " + why + " (" + fit + ")";
  return nullptr;
}

}  // namespace cuda
}  // namespace hapi_eskf
