// Launch wrappers of the partitioned CUDA backend's own kernels
// (partitioned_cuda_backend.cpp, docs/DESIGN.md "Partitioned update"): the
// gathers that move rows and columns between the stored C, the basis columns
// X and the active blocks, the measurement scatter and the flush's write-back
// of the active rows. All O(n a) or less; the products are cuBLAS's. FP64.
// Every wrapper enqueues on `stream` and returns the launch status.
#pragma once

#include <cuda_runtime.h>

#include <cstddef>

namespace hapi_eskf {
namespace cuda {

// out(i, t) = M(r_i, c_t) of the symmetric M stored by its lower triangle,
// r_i = rows[i] (rows null: r_i = i) for i < nr, c_t = cols[t] for t < nc;
// out has leading dim ldo. Tiled so that both the lower and the mirrored
// upper reads stay inside one column of M per warp.
cudaError_t launchGatherSymmetric(const double* M, std::size_t ldm, const int* rows, int nr, const int* cols, int nc,
                                  double* out, std::size_t ldo, cudaStream_t stream);

// out(i, c) = M(rows[i], c) of a general column-major M, i < nr, c < nc.
cudaError_t launchGatherRows(const double* M, std::size_t ldm, const int* rows, int nr, int nc, double* out,
                             std::size_t ldo, cudaStream_t stream);

// M(i, i) = 1 for i < n (the rest untouched).
cudaError_t launchSetDiagonalOne(double* M, std::size_t ldm, int n, cudaStream_t stream);

// H_A^T and R of m measurement blocks in the active ordering: for block j
// (H: 27 values, row-major 3x6 pose then 3x3 landmark; R: 9, row-major) and
// active row l_j = active_row[j] of its landmark, column 3j + r of Ht (a x 3m,
// leading dim ldh, zeroed by the caller) gets Hp_j(r, :) in rows 0..5 and
// Hl_j(r, :) in rows l_j..l_j+2, and S (3m x 3m, zeroed) gets R_j on its
// diagonal block j.
cudaError_t launchScatterMeasurements(const double* H, const double* R, const int* active_row, int m, double* Ht,
                                      std::size_t ldh, double* S, cudaStream_t stream);

// The flush's write-back of active rows ia0 .. ia0 + w - 1 into the stored C
// (lower triangle): for each such ia not marked in skip, with s =
// state_of_active[ia] and every state index j < n,
//   C(s, j) = Caa(ia, active_of_state[j]) where j is active (>= 0),
//   C(s, j) = Rt(j, ia - ia0)             otherwise,
// Rt n x w with leading dim n (the rows of Phi X^T, transposed). Two active
// rows write their common entry with the same value (Caa's lower element).
cudaError_t launchWriteActiveRows(double* C, std::size_t ld, int n, const double* Rt, int ia0, int w,
                                  const int* state_of_active, const int* active_of_state, const double* Caa,
                                  std::size_t lda, const unsigned char* skip, cudaStream_t stream);

// --- Staged flush (docs/DESIGN.md "Staged flush", staged_flush.hpp) ---

// M(rows[i], c) = 0 for i < nr, c < nc.
cudaError_t launchZeroRows(double* M, std::size_t ldm, const int* rows, int nr, int nc, cudaStream_t stream);

// What gathered entries still owe: out(i, u) -= D(r_i, u) where
// max(r_i, cols[u]) >= done, r_i = rows[i] (rows null: r_i = i), i < nr,
// u < nc; D (leading dim ldd) holds Xp Psip Xp_cols^T by state row.
cudaError_t launchSubtractOwed(double* out, std::size_t ldo, const int* rows, int nr, const int* cols, int nc,
                               const double* D, std::size_t ldd, int done, cudaStream_t stream);

// Entries settled by a removal's moves: for the state rows ks[u] (u < w,
// flagged in `settled`, length >= done) and every row i < done, the stored
// lower entry (max(i, k), min(i, k)) -= D(i, u); a pair of two settled rows
// once (skipped where i is settled and i > k).
cudaError_t launchSettleOwed(double* C, std::size_t ld, const int* ks, int w, const double* D, std::size_t ldd,
                             int done, const unsigned char* settled, cudaStream_t stream);

}  // namespace cuda
}  // namespace hapi_eskf
