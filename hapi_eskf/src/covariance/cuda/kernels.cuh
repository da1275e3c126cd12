// Launch wrappers of the CUDA backend's own kernels (gather, small products,
// bookkeeping, association). Plain pointers only: no Eigen in device code.
// Storage (covariance_backend.hpp contract): C is column-major with leading
// dimension ld >= P + 3 * capacity (blas_traits.hpp paddedLd), P = pose_dim
// the pose block (types.hpp; 12 or 18); only the LOWER
// triangle is read or written (element (i, j) with i < j is read as
// C[j + i * ld]).
// Every wrapper enqueues on `stream` and returns the launch status; the host
// class synchronises and checks at the end of each backend call.
#pragma once

#include <cuda_runtime.h>

#include <cstddef>
#include <cstdint>

namespace hapi_eskf {
namespace cuda {

// --- update (docs/DESIGN.md "Update" steps 1-2) ----------------------------
// P(:, 3j + r) = C H_j^T for every measurement block j (9 non-zero columns):
// H_j = [Hp_j (3x6 pose) | Hl_j (3x3 at slot_j)]. `H` holds 27 values per
// block, row-major Hp then row-major Hl. P is n x 3m with leading dim ldP.
template <typename T>
cudaError_t launchGatherPHt(const T* C, std::size_t ld, int n, int pose_dim, const int* slots, const T* H, int m,
                            T* P, std::size_t ldP, cudaStream_t stream);

// S = H P + R (3m x 3m, leading dim 3m, full matrix). R holds 9 values per
// block (row-major).
template <typename T>
cudaError_t launchInnovationCov(const T* P, std::size_t ldP, int pose_dim, const int* slots, const T* H, const T* R,
                                int m, T* S, cudaStream_t stream);

// *flag <- 1 if any of x[0..count) is NaN or Inf (flag zeroed by the caller).
template <typename T>
cudaError_t launchCountNonFinite(const T* x, std::size_t count, int* flag, cudaStream_t stream);

// M(i, j) = 0 for i < j (n x n, leading dim n): the inverse factor from
// trtri keeps S's upper triangle, which a plain GEMM with it must not see.
template <typename T>
cudaError_t launchZeroStrictUpper(T* M, int n, cudaStream_t stream);

// --- predict (docs/DESIGN.md "Predict") ---------------------------------------
// C_pp <- F C_pp F^T + Q, C_mp <- C_mp F^T (rows P..n-1), lower triangle.
// F and Q: P x P row-major in device memory (2 x 18^2 doubles exceed the
// classic 4 KB kernel-parameter limit). pose_dim 12 or 18, else
// cudaErrorInvalidValue.
template <typename T>
cudaError_t launchPredict(T* C, std::size_t ld, int n, int pose_dim, const double* F, const double* Q,
                          cudaStream_t stream);

// --- read-back helpers ----------------------------------------------------------
// out[s * 81 + a + 9 * b] = C(idx_a, idx_b) with idx = [0..5, row(slot_s)..+2].
template <typename T>
cudaError_t launchMarginals(const T* C, std::size_t ld, int pose_dim, const int* slots, int count, double* out,
                            cudaStream_t stream);
// out[k * 9 + a + 3 * b] = C(row(k) + a, row(k) + b) for k < K.
template <typename T>
cudaError_t launchLandmarkBlocks(const T* C, std::size_t ld, int pose_dim, int K, double* out, cudaStream_t stream);

// --- bookkeeping (docs/DESIGN.md "New landmark", "Removal") ----------------------
// Appends m landmarks after the first n_old rows: G holds 18 values per block
// (row-major G_pose, 3x6); Nz holds 9 per block (G_z Cz G_z^T, row-major).
template <typename T>
cudaError_t launchAddLandmarks(T* C, std::size_t ld, int n_old, const T* G, const T* Nz, int m,
                               cudaStream_t stream);

// Removal by filling holes from the tail (removal_plan.hpp): for each of the
// h moved landmarks (new slot holes[t], old slot old_slot_of_new[holes[t]])
// and every j < n_new, C(D, j) = C_old(S, old(j)) with D / S its new / old
// rows and old(j) the old index of new row j (old_slot_of_new has K_new
// entries). Reads touch rows >= n_new only, writes rows and columns < n_new
// only, so the pass is race-free in place. O(3 h n_new) elements.
template <typename T>
cudaError_t launchFillHoles(T* C, std::size_t ld, int n_new, int pose_dim, const int* old_slot_of_new,
                            const int* holes, int h, cudaStream_t stream);

// Descriptor rows: dst[k] = src[keep[k]] for k < count (D bytes each).
cudaError_t launchGatherDescriptors(const uint8_t* src, const int* keep, int count, int D, uint8_t* dst,
                                    cudaStream_t stream);

// --- association -------------------------------------------------------------------
// Best and second-best pool slot per query by Hamming distance; ties go to the
// lower slot (lexicographic order of (distance, slot)). -1 / 1 << 30 when none.
cudaError_t launchHammingTop2(const uint8_t* pool, int K, const uint8_t* queries, int n_query, int D,
                              int* best_slot, int* best_dist, int* second_slot, int* second_dist,
                              cudaStream_t stream);

}  // namespace cuda
}  // namespace hapi_eskf
