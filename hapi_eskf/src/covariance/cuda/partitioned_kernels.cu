// Own kernels of the partitioned CUDA backend (partitioned_kernels.cuh).
#include "partitioned_kernels.cuh"
#include "lower_triangle.cuh"

namespace hapi_eskf {
namespace cuda {
namespace {

constexpr int kThreads = 256;
constexpr int kTile = 32, kTileRows = 8;

inline unsigned blocksFor(long long count) { return static_cast<unsigned>((count + kThreads - 1) / kThreads); }
inline unsigned gridY(int count) { return static_cast<unsigned>(count < 65535 ? count : 65535); }

// Tile of 32 output rows i x 32 output columns t. First the lanes run over t:
// the entries above the diagonal (r_i < c_t) are M(c_t, r_i), stored in column
// r_i, so a warp reads one column; they go through shared memory. Then the
// lanes run over i: the entries on or below the diagonal are M(r_i, c_t) in
// column c_t (contiguous for consecutive rows), and the output columns are
// written coalesced.
__global__ void gatherSymmetricKernel(const double* __restrict__ M, std::size_t ldm, const int* __restrict__ rows,
                                      int nr, const int* __restrict__ cols, int nc, double* __restrict__ out,
                                      std::size_t ldo) {
  __shared__ double tile[kTile][kTile + 1];
  const int i0 = blockIdx.x * kTile, t0 = blockIdx.y * kTile;
  const int tx = threadIdx.x, ty = threadIdx.y;
  {
    const int t = t0 + tx;
    const int c = t < nc ? cols[t] : 0;
    for (int ii = ty; ii < kTile; ii += kTileRows) {
      const int i = i0 + ii;
      double v = 0.0;
      if (t < nc && i < nr) {
        const int r = rows != nullptr ? rows[i] : i;
        if (r < c) v = M[c + static_cast<std::size_t>(r) * ldm];
      }
      tile[ii][tx] = v;
    }
  }
  __syncthreads();
  const int i = i0 + tx;
  if (i >= nr) return;
  const int r = rows != nullptr ? rows[i] : i;
  for (int tt = ty; tt < kTile; tt += kTileRows) {
    const int t = t0 + tt;
    if (t >= nc) break;
    const int c = cols[t];
    out[i + static_cast<std::size_t>(t) * ldo] = r >= c ? M[r + static_cast<std::size_t>(c) * ldm] : tile[tx][tt];
  }
}

__global__ void gatherRowsKernel(const double* __restrict__ M, std::size_t ldm, const int* __restrict__ rows, int nr,
                                 int nc, double* __restrict__ out, std::size_t ldo) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= nr) return;
  const std::size_t r = static_cast<std::size_t>(rows[i]);
  for (int c = blockIdx.y; c < nc; c += gridDim.y)
    out[i + static_cast<std::size_t>(c) * ldo] = M[r + static_cast<std::size_t>(c) * ldm];
}

__global__ void setDiagonalOneKernel(double* __restrict__ M, std::size_t ldm, int n) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) M[i + static_cast<std::size_t>(i) * ldm] = 1.0;
}

// One thread per row q = 3j + r of H_A.
__global__ void scatterMeasurementsKernel(const double* __restrict__ H, const double* __restrict__ R,
                                          const int* __restrict__ active_row, int m, double* __restrict__ Ht,
                                          std::size_t ldh, double* __restrict__ S) {
  const int q = blockIdx.x * blockDim.x + threadIdx.x;
  if (q >= 3 * m) return;
  const int j = q / 3, r = q % 3;
  const int l = active_row[j];
  const double* h = H + 27 * j;
  double* col = Ht + static_cast<std::size_t>(q) * ldh;
#pragma unroll
  for (int c = 0; c < 6; ++c) col[c] = h[6 * r + c];
#pragma unroll
  for (int c = 0; c < 3; ++c) col[l + c] = h[18 + 3 * r + c];
  const std::size_t dim = 3 * static_cast<std::size_t>(m);
#pragma unroll
  for (int c = 0; c < 3; ++c) S[q + static_cast<std::size_t>(3 * j + c) * dim] = R[9 * j + 3 * r + c];
}

// One thread per (state index j, active row): the entry on or below the
// diagonal of (s, j), read from Caa or Rt.
__global__ void writeActiveRowsKernel(double* __restrict__ C, std::size_t ld, int n, const double* __restrict__ Rt,
                                      int ia0, int w, const int* __restrict__ state_of_active,
                                      const int* __restrict__ active_of_state, const double* __restrict__ Caa,
                                      std::size_t lda, const unsigned char* __restrict__ skip) {
  const int j = blockIdx.x * blockDim.x + threadIdx.x;
  if (j >= n) return;
  const int jb = active_of_state[j];
  for (int u = blockIdx.y; u < w; u += gridDim.y) {
    const int ia = ia0 + u;
    if (skip[ia]) continue;
    const int s = state_of_active[ia];
    const double v = jb >= 0 ? sym(Caa, lda, ia, jb) : Rt[j + static_cast<std::size_t>(u) * n];
    C[static_cast<std::size_t>(max(s, j)) + static_cast<std::size_t>(min(s, j)) * ld] = v;
  }
}

__global__ void zeroRowsKernel(double* __restrict__ M, std::size_t ldm, const int* __restrict__ rows, int nr,
                               int nc) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= nr) return;
  const std::size_t r = static_cast<std::size_t>(rows[i]);
  for (int c = blockIdx.y; c < nc; c += gridDim.y) M[r + static_cast<std::size_t>(c) * ldm] = 0.0;
}

__global__ void subtractOwedKernel(double* __restrict__ out, std::size_t ldo, const int* __restrict__ rows, int nr,
                                   const int* __restrict__ cols, int nc, const double* __restrict__ D,
                                   std::size_t ldd, int done) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= nr) return;
  const int r = rows != nullptr ? rows[i] : i;
  for (int u = blockIdx.y; u < nc; u += gridDim.y)
    if (max(r, cols[u]) >= done)
      out[i + static_cast<std::size_t>(u) * ldo] -= D[static_cast<std::size_t>(r) + static_cast<std::size_t>(u) * ldd];
}

__global__ void settleOwedKernel(double* __restrict__ C, std::size_t ld, const int* __restrict__ ks, int w,
                                 const double* __restrict__ D, std::size_t ldd, int done,
                                 const unsigned char* __restrict__ settled) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= done) return;
  for (int u = blockIdx.y; u < w; u += gridDim.y) {
    const int k = ks[u];
    if (settled[i] && i > k) continue;
    C[static_cast<std::size_t>(max(i, k)) + static_cast<std::size_t>(min(i, k)) * ld] -=
        D[i + static_cast<std::size_t>(u) * ldd];
  }
}

}  // namespace

cudaError_t launchZeroRows(double* M, std::size_t ldm, const int* rows, int nr, int nc, cudaStream_t stream) {
  if (nr <= 0 || nc <= 0) return cudaSuccess;
  zeroRowsKernel<<<dim3(blocksFor(nr), gridY(nc)), kThreads, 0, stream>>>(M, ldm, rows, nr, nc);
  return cudaGetLastError();
}

cudaError_t launchSubtractOwed(double* out, std::size_t ldo, const int* rows, int nr, const int* cols, int nc,
                               const double* D, std::size_t ldd, int done, cudaStream_t stream) {
  if (nr <= 0 || nc <= 0) return cudaSuccess;
  subtractOwedKernel<<<dim3(blocksFor(nr), gridY(nc)), kThreads, 0, stream>>>(out, ldo, rows, nr, cols, nc, D, ldd,
                                                                              done);
  return cudaGetLastError();
}

cudaError_t launchSettleOwed(double* C, std::size_t ld, const int* ks, int w, const double* D, std::size_t ldd,
                             int done, const unsigned char* settled, cudaStream_t stream) {
  if (w <= 0 || done <= 0) return cudaSuccess;
  settleOwedKernel<<<dim3(blocksFor(done), gridY(w)), kThreads, 0, stream>>>(C, ld, ks, w, D, ldd, done, settled);
  return cudaGetLastError();
}

cudaError_t launchGatherSymmetric(const double* M, std::size_t ldm, const int* rows, int nr, const int* cols, int nc,
                                  double* out, std::size_t ldo, cudaStream_t stream) {
  if (nr <= 0 || nc <= 0) return cudaSuccess;
  const dim3 grid((nr + kTile - 1) / kTile, (nc + kTile - 1) / kTile);
  gatherSymmetricKernel<<<grid, dim3(kTile, kTileRows), 0, stream>>>(M, ldm, rows, nr, cols, nc, out, ldo);
  return cudaGetLastError();
}

cudaError_t launchGatherRows(const double* M, std::size_t ldm, const int* rows, int nr, int nc, double* out,
                             std::size_t ldo, cudaStream_t stream) {
  if (nr <= 0 || nc <= 0) return cudaSuccess;
  gatherRowsKernel<<<dim3(blocksFor(nr), gridY(nc)), kThreads, 0, stream>>>(M, ldm, rows, nr, nc, out, ldo);
  return cudaGetLastError();
}

cudaError_t launchSetDiagonalOne(double* M, std::size_t ldm, int n, cudaStream_t stream) {
  if (n <= 0) return cudaSuccess;
  setDiagonalOneKernel<<<blocksFor(n), kThreads, 0, stream>>>(M, ldm, n);
  return cudaGetLastError();
}

cudaError_t launchScatterMeasurements(const double* H, const double* R, const int* active_row, int m, double* Ht,
                                      std::size_t ldh, double* S, cudaStream_t stream) {
  if (m <= 0) return cudaSuccess;
  scatterMeasurementsKernel<<<blocksFor(3 * m), kThreads, 0, stream>>>(H, R, active_row, m, Ht, ldh, S);
  return cudaGetLastError();
}

cudaError_t launchWriteActiveRows(double* C, std::size_t ld, int n, const double* Rt, int ia0, int w,
                                  const int* state_of_active, const int* active_of_state, const double* Caa,
                                  std::size_t lda, const unsigned char* skip, cudaStream_t stream) {
  if (n <= 0 || w <= 0) return cudaSuccess;
  writeActiveRowsKernel<<<dim3(blocksFor(n), gridY(w)), kThreads, 0, stream>>>(C, ld, n, Rt, ia0, w, state_of_active,
                                                                                active_of_state, Caa, lda, skip);
  return cudaGetLastError();
}

}  // namespace cuda
}  // namespace hapi_eskf
