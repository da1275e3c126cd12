// Device-side reads of a symmetric matrix stored by its LOWER triangle (the
// covariance_backend.hpp storage contract), written once for every kernel file.
#pragma once

#include <cstddef>

namespace hapi_eskf {
namespace cuda {

// Element (i, j): above the diagonal it is read mirrored.
template <typename T>
__device__ __forceinline__ T sym(const T* C, std::size_t ld, int i, int j) {
  return i >= j ? C[i + static_cast<std::size_t>(j) * ld] : C[j + static_cast<std::size_t>(i) * ld];
}

// Row of a landmark slot after the pose block of P rows (types.hpp landmarkRow).
__device__ __forceinline__ int landmarkRowDev(int slot, int P) { return P + 3 * slot; }

}  // namespace cuda
}  // namespace hapi_eskf
