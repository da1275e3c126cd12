// Storage selection from the settings (storage_factory.hpp); the CUDA entry
// points are compiled in only when src/covariance/cuda was built
// (HAPI_ESKF_WITH_CUDA).
#include "hapi_eskf/eskf/storage_factory.hpp"

#include "../covariance/cpu_linear_algebra.hpp"
#include "hapi_eskf/eskf/frame_error_block.hpp"
#include "hapi_eskf/eskf/motion_model.hpp"

#ifdef HAPI_ESKF_WITH_CUDA
#include "hapi_eskf/covariance/cuda_backend.hpp"
#endif

namespace hapi_eskf {

bool cudaBackendAvailable(int device, std::string* why) {
#ifdef HAPI_ESKF_WITH_CUDA
  std::string info;
  const bool ok = cuda::deviceAvailable(device, &info);
  if (why) *why = info;
  return ok;
#else
  if (why)
    *why = "CUDA device " + std::to_string(device) +
           ": hapi_eskf was built without CUDA (HAPI_WITH_CUDA=OFF or nvcc not found)";
  return false;
#endif
}

bool cudaPoolFits(const EskfSettings& s, int descriptor_length, std::string* why) {
#ifdef HAPI_ESKF_WITH_CUDA
  return cuda::poolFits(s.max_landmarks, descriptor_length, filterPoseDim(s), s, why);
#else
  return cudaBackendAvailable(s.cuda_device, why);
#endif
}

std::unique_ptr<CovarianceBackend> makeBackend(const EskfSettings& s, int descriptor_length, std::string* error) {
  const std::string bad = s.validate();
  if (!bad.empty()) {
    if (error) *error = bad;
    return nullptr;
  }
  if (descriptor_length < 0) {
    if (error) *error = "descriptor_length must be >= 0";
    return nullptr;
  }
  if (s.backend == BackendKind::kCpu) {
    if (s.precision != Precision::kFp64) {
      if (error) *error = "the cpu backend supports precision fp64 only";
      return nullptr;
    }
    if (s.cpu_linear_algebra == CpuLinearAlgebra::kBlas) cpu_la::setBlasThreads(s.cpu_blas_threads);
    if (s.covariance_update == CovarianceUpdate::kPartitioned)
      return makePartitionedCpuBackend(s.max_landmarks, descriptor_length, filterPoseDim(s),
                                       s.cpu_linear_algebra, s.partition_max_active, s.partition_flush_shares,
                                       s.partition_flush_background);
    return makeCpuBackend(s.max_landmarks, descriptor_length, filterPoseDim(s), s.cpu_linear_algebra);
  }
#ifdef HAPI_ESKF_WITH_CUDA
  std::string err;
  auto b = s.covariance_update == CovarianceUpdate::kPartitioned
               ? cuda::makePartitionedCudaBackend(s.max_landmarks, descriptor_length, filterPoseDim(s), s, &err)
               : cuda::makeCudaBackend(s.max_landmarks, descriptor_length, filterPoseDim(s), s, &err);
  if (!b && error) *error = err.empty() ? std::string("cuda backend creation failed") : err;
  return b;
#else
  if (error) *error = "backend 'cuda' requested but hapi_eskf was built without CUDA";
  return nullptr;
#endif
}

}  // namespace hapi_eskf
