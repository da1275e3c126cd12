// Status plumbing: every CUDA runtime / cuBLAS / cuSOLVER result is checked
// and turned into Status::kBackendError with a readable reason (bad
// input or a failing device never crashes the filter).
#pragma once

#include <cublas_v2.h>
#include <cuda_runtime.h>
#include <cusolverDn.h>

#include <string>

namespace hapi_eskf {
namespace cuda {

inline bool failed(cudaError_t e, const char* what, std::string* why) {
  if (e == cudaSuccess) return false;
  *why = std::string(what) + ": " + cudaGetErrorString(e);
  // The runtime also keeps a failed call (e.g. an out-of-memory cudaMalloc)
  // as its "last error", which the kernel-launch checks read: left there, it
  // would fail the next launch of any backend in this process, also one
  // created after the memory came back. Reading it clears it; a sticky error
  // (a corrupted context) is returned again by the next call anyway.
  cudaGetLastError();
  return true;
}
inline bool failed(cublasStatus_t e, const char* what, std::string* why) {
  if (e == CUBLAS_STATUS_SUCCESS) return false;
  *why = std::string(what) + ": cuBLAS status " + std::to_string(static_cast<int>(e));
  return true;
}
inline bool failed(cusolverStatus_t e, const char* what, std::string* why) {
  if (e == CUSOLVER_STATUS_SUCCESS) return false;
  *why = std::string(what) + ": cuSOLVER status " + std::to_string(static_cast<int>(e));
  return true;
}

}  // namespace cuda
}  // namespace hapi_eskf

// Inside a backend method returning Status; `last_error_` is the member that
// keeps the reason for diagnostics.
#define HAPI_CUDA_TRY(expr)                                          \
  do {                                                               \
    if (::hapi_eskf::cuda::failed((expr), #expr, &last_error_)) {    \
      return ::hapi_eskf::Status::kBackendError;                     \
    }                                                                \
  } while (0)
