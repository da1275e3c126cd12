// Internal: turn CUDA runtime errors into exceptions with the failing call.
#pragma once

#include <cuda_runtime.h>

#include <stdexcept>
#include <string>

namespace hapi_frontend {
namespace cuda_detail {

inline void check(cudaError_t e, const char* what, const char* file, int line) {
  if (e != cudaSuccess) {
    throw std::runtime_error(std::string("CUDA error in ") + what + " (" + file + ":" + std::to_string(line) +
                             "): " + cudaGetErrorString(e));
  }
}

}  // namespace cuda_detail
}  // namespace hapi_frontend

#define HAPI_CUDA_CHECK(call) ::hapi_frontend::cuda_detail::check((call), #call, __FILE__, __LINE__)
