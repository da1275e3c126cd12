// Cholesky factor of the innovation covariance S on the device with the CPU
// reference's checks (docs/DESIGN.md "Update"), written once for the dense and
// the partitioned CUDA backends: a non-finite S is kNonFinite, a failed or
// numerically singular factor (min L_ii <= 1e-12 sqrt(max S_ii))
// kNotPositiveDefinite. Two halves around the caller's stream synchronisation,
// so the dense backend's stage events stay where they were.
#pragma once

#include "blas_traits.hpp"
#include "cuda_check.hpp"
#include "device_buffer.hpp"
#include "kernels.cuh"

#include "hapi_eskf/status.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace hapi_eskf {
namespace cuda {

template <typename T>
class InnovationFactor {
 public:
  // Enqueues the finiteness check of S (dim x dim, leading dim dim) and the
  // read-back of diag(S). kBackendError and *why on a failed call.
  Status enqueueCheck(cudaStream_t stream, const T* S, int dim, std::string* why) {
    dim_ = dim;
    diag_s_.resize(dim);
    diag_l_.resize(dim);
    info_[0] = info_[1] = 0;
    if (failed(flags_.ensure(2), "cudaMalloc(flags)", why) ||
        failed(cudaMemsetAsync(flags_.get(), 0, 2 * sizeof(int), stream), "cudaMemsetAsync(flags)", why) ||
        failed(launchCountNonFinite<T>(S, static_cast<std::size_t>(dim) * dim, flags_.get() + 1, stream),
               "launchCountNonFinite", why) ||
        failed(cudaMemcpy2DAsync(diag_s_.data(), sizeof(T), S, (dim + 1) * sizeof(T), sizeof(T), dim,
                                 cudaMemcpyDeviceToHost, stream),
               "cudaMemcpy2DAsync(diag S)", why))
      return Status::kBackendError;
    return Status::kOk;
  }

  // Enqueues potrf (lower, in place) and the read-back of its info and diag(L).
  Status enqueueFactor(cusolverDnHandle_t solver, cudaStream_t stream, T* S, std::string* why) {
    int lwork = 0;
    if (failed(Blas<T>::potrfBufferSize(solver, dim_, S, dim_, &lwork), "potrfBufferSize", why) ||
        failed(work_.ensure(static_cast<std::size_t>(std::max(lwork, 1))), "cudaMalloc(potrf work)", why) ||
        failed(Blas<T>::potrf(solver, dim_, S, dim_, work_.get(), lwork, flags_.get()), "potrf", why) ||
        failed(cudaMemcpyAsync(info_, flags_.get(), 2 * sizeof(int), cudaMemcpyDeviceToHost, stream),
               "cudaMemcpyAsync(info)", why) ||
        failed(cudaMemcpy2DAsync(diag_l_.data(), sizeof(T), S, (dim_ + 1) * sizeof(T), sizeof(T), dim_,
                                 cudaMemcpyDeviceToHost, stream),
               "cudaMemcpy2DAsync(diag L)", why))
      return Status::kBackendError;
    return Status::kOk;
  }

  // After the stream has synchronised: the verdict on S and its factor.
  Status verdict(std::string* why) const {
    if (info_[1] != 0) return Status::kNonFinite;
    if (info_[0] > 0) return Status::kNotPositiveDefinite;
    if (info_[0] < 0) {
      *why = "potrf: invalid argument " + std::to_string(-info_[0]);
      return Status::kBackendError;
    }
    double max_s = 1e-300, min_l = std::numeric_limits<double>::infinity();
    for (int i = 0; i < dim_; ++i) {
      max_s = std::max(max_s, static_cast<double>(diag_s_[i]));
      min_l = std::min(min_l, static_cast<double>(diag_l_[i]));
    }
    if (!(min_l > 1e-12 * std::sqrt(max_s))) return Status::kNotPositiveDefinite;
    return Status::kOk;
  }

  std::size_t bytes() const { return work_.bytes() + flags_.bytes(); }

 private:
  DeviceBuffer<T> work_;
  DeviceBuffer<int> flags_;  // potrf info | non-finite flag
  std::vector<T> diag_s_, diag_l_;
  int info_[2] = {0, 0};
  int dim_ = 0;
};

}  // namespace cuda
}  // namespace hapi_eskf
