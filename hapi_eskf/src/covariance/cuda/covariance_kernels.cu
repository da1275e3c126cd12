// Own kernels of the update, predict and read-back paths (docs/DESIGN.md "CUDA backend").
// All of them touch O(n) or O(m^2) elements; the O(n^2 m) work is cuBLAS's.
#include "kernels.cuh"
#include "lower_triangle.cuh"

namespace hapi_eskf {
namespace cuda {
namespace {

constexpr int kThreads = 256;

// One thread per (state row i, measurement j): reads the 9 columns of C that
// H_j touches and writes 3 entries of P. Threads of a warp share j, so the H
// loads are broadcasts and the C loads are coalesced along i: the pose columns
// (i >= 6) and, for rows i >= l below the landmark's diagonal block, the
// landmark columns. The landmark part of rows i < l lives in the UPPER
// triangle, i.e. in row l..l+2 of column i (stride ld across the warp: one
// 768 KB page per thread at K = 32000); gatherUpperKernel adds it with
// column-local reads, so here it is left out.
template <typename T>
__global__ void gatherPHtKernel(const T* __restrict__ C, std::size_t ld, int n, int pose_dim,
                                const int* __restrict__ slots, const T* __restrict__ H, T* __restrict__ P,
                                std::size_t ldP) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  const int j = blockIdx.y;
  if (i >= n) return;
  const int l = landmarkRowDev(slots[j], pose_dim);
  T v[9];
#pragma unroll
  for (int c = 0; c < 6; ++c) v[c] = sym(C, ld, i, c);
#pragma unroll
  for (int c = 0; c < 3; ++c) v[6 + c] = i >= l ? sym(C, ld, i, l + c) : T(0);
  const T* h = H + 27 * j;
#pragma unroll
  for (int r = 0; r < 3; ++r) {
    T acc = 0;
#pragma unroll
    for (int c = 0; c < 6; ++c) acc += h[6 * r + c] * v[c];
#pragma unroll
    for (int c = 0; c < 3; ++c) acc += h[18 + 3 * r + c] * v[6 + c];
    P[i + static_cast<std::size_t>(3 * j + r) * ldP] = acc;
  }
}

// P(i, 3j + r) += Hl_j(r, :) C(l_j .. l_j + 2, i) for rows i < l_j (run after
// gatherPHtKernel). Tile of 32 rows i x 32 measurements j: first the lanes run
// over j, so a warp reads 32 short runs inside ONE column i of C (page-local);
// the products go through shared memory and are written with the lanes over
// i (coalesced columns of P).
constexpr int kTile = 32, kTileRows = 8;
template <typename T>
__global__ void gatherUpperKernel(const T* __restrict__ C, std::size_t ld, int n, int pose_dim,
                                  const int* __restrict__ slots, const T* __restrict__ H, int m, T* __restrict__ P,
                                  std::size_t ldP) {
  __shared__ T tile[3][kTile][kTile + 1];
  const int i0 = blockIdx.x * kTile, j0 = blockIdx.y * kTile;
  const int tx = threadIdx.x, ty = threadIdx.y;
  {
    const int j = j0 + tx;
    const int l = j < m ? landmarkRowDev(slots[j], pose_dim) : 0;
    const T* h = H + 27 * (j < m ? j : 0) + 18;
    for (int ii = ty; ii < kTile; ii += kTileRows) {
      const int i = i0 + ii;
      T a[3] = {T(0), T(0), T(0)};
      if (j < m && i < l && i < n) {
        const T* col = C + static_cast<std::size_t>(i) * ld + l;  // C(l.., i), upper part of column l..
        const T v0 = col[0], v1 = col[1], v2 = col[2];
#pragma unroll
        for (int r = 0; r < 3; ++r) a[r] = h[3 * r] * v0 + h[3 * r + 1] * v1 + h[3 * r + 2] * v2;
      }
#pragma unroll
      for (int r = 0; r < 3; ++r) tile[r][tx][ii] = a[r];
    }
  }
  __syncthreads();
  const int i = i0 + tx;
  for (int jj = ty; jj < kTile; jj += kTileRows) {
    const int j = j0 + jj;
    if (j >= m || i >= n || i >= landmarkRowDev(slots[j], pose_dim)) continue;
#pragma unroll
    for (int r = 0; r < 3; ++r) P[i + static_cast<std::size_t>(3 * j + r) * ldP] += tile[r][jj][tx];
  }
}

// S(a, b) = H_a-row . P(:, b) using only the 9 non-zero columns of the row.
template <typename T>
__global__ void innovationCovKernel(const T* __restrict__ P, std::size_t ldP, int pose_dim,
                                    const int* __restrict__ slots, const T* __restrict__ H, const T* __restrict__ R,
                                    int m, T* __restrict__ S) {
  const int dim = 3 * m;
  const int a = blockIdx.y;  // row of S
  const int b = blockIdx.x * blockDim.x + threadIdx.x;
  if (b >= dim) return;
  const int j = a / 3, r = a % 3;
  const int l = landmarkRowDev(slots[j], pose_dim);
  const T* h = H + 27 * j;
  const T* p = P + static_cast<std::size_t>(b) * ldP;
  T acc = 0;
#pragma unroll
  for (int c = 0; c < 6; ++c) acc += h[6 * r + c] * p[c];
#pragma unroll
  for (int c = 0; c < 3; ++c) acc += h[18 + 3 * r + c] * p[l + c];
  if (b / 3 == j) acc += R[9 * j + 3 * r + (b % 3)];
  S[a + static_cast<std::size_t>(b) * dim] = acc;
}

template <typename T>
__global__ void nonFiniteKernel(const T* __restrict__ x, std::size_t count, int* flag) {
  const std::size_t i = static_cast<std::size_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < count && !isfinite(x[i])) *flag = 1;
}

// C_mp <- C_mp F^T: row i (>= P) of the cross block is P values in the
// lower triangle, C[i + c ld]; coalesced across the warp. F is P x P
// row-major in device memory (read through the cache by every thread).
template <typename T, int P>
__global__ void predictCrossKernel(T* __restrict__ C, std::size_t ld, int n, const double* __restrict__ F) {
  const int i = P + blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  double row[P];
#pragma unroll
  for (int c = 0; c < P; ++c) row[c] = C[i + static_cast<std::size_t>(c) * ld];
#pragma unroll
  for (int c = 0; c < P; ++c) {
    double acc = 0;
#pragma unroll
    for (int d = 0; d < P; ++d) acc += F[P * c + d] * row[d];
    C[i + static_cast<std::size_t>(c) * ld] = static_cast<T>(acc);
  }
}

// C_pp <- F C_pp F^T + Q in one block of P^2 threads (shared P x P tiles).
template <typename T, int P>
__global__ void predictPoseKernel(T* __restrict__ C, std::size_t ld, const double* __restrict__ F,
                                  const double* __restrict__ Q) {
  __shared__ double cpp[P * P], fc[P * P];
  const int t = threadIdx.x;
  const int r = t / P, c = t % P;
  cpp[t] = sym(C, ld, r, c);
  __syncthreads();
  double acc = 0;
  for (int k = 0; k < P; ++k) acc += F[P * r + k] * cpp[P * k + c];
  fc[t] = acc;  // (F C)(r, c)
  __syncthreads();
  acc = Q[t];
  for (int k = 0; k < P; ++k) acc += fc[P * r + k] * F[P * c + k];
  if (r >= c) C[r + static_cast<std::size_t>(c) * ld] = static_cast<T>(acc);
}

template <typename T>
__global__ void marginalsKernel(const T* __restrict__ C, std::size_t ld, int pose_dim, const int* __restrict__ slots,
                                double* __restrict__ out) {
  const int s = blockIdx.x;
  const int t = threadIdx.x;  // 81 threads
  const int a = t % 9, b = t / 9;
  const int l = landmarkRowDev(slots[s], pose_dim);
  const int ia = a < 6 ? a : l + a - 6;
  const int ib = b < 6 ? b : l + b - 6;
  out[81 * s + a + 9 * b] = static_cast<double>(sym(C, ld, ia, ib));
}

template <typename T>
__global__ void landmarkBlocksKernel(const T* __restrict__ C, std::size_t ld, int pose_dim, int K,
                                     double* __restrict__ out) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= K) return;
  const int l = landmarkRowDev(k, pose_dim);
#pragma unroll
  for (int b = 0; b < 3; ++b)
#pragma unroll
    for (int a = 0; a < 3; ++a) out[9 * k + a + 3 * b] = static_cast<double>(sym(C, ld, l + a, l + b));
}

// New rows n_old + 3b + r, column j < n_old: G_b C_[dp dtheta], j.
template <typename T>
__global__ void addCrossKernel(T* __restrict__ C, std::size_t ld, int n_old, const T* __restrict__ G, int m) {
  const int j = blockIdx.x * blockDim.x + threadIdx.x;
  if (j >= n_old) return;
  double v[6];
#pragma unroll
  for (int c = 0; c < 6; ++c) v[c] = sym(C, ld, c, j);
  T* col = C + static_cast<std::size_t>(j) * ld + n_old;
  for (int b = 0; b < m; ++b) {
    const T* g = G + 18 * b;
#pragma unroll
    for (int r = 0; r < 3; ++r) {
      double acc = 0;
#pragma unroll
      for (int c = 0; c < 6; ++c) acc += g[6 * r + c] * v[c];
      col[3 * b + r] = static_cast<T>(acc);
    }
  }
}

// New-new block (lower part): G_i C_66 G_j^T (+ G_z Cz G_z^T on the diagonal).
template <typename T>
__global__ void addNewNewKernel(T* __restrict__ C, std::size_t ld, int n_old, const T* __restrict__ G,
                                const T* __restrict__ Nz, int m) {
  __shared__ double c66[36];
  if (threadIdx.x < 36) c66[threadIdx.x] = sym(C, ld, threadIdx.x % 6, threadIdx.x / 6);
  __syncthreads();
  const int a = blockIdx.y;  // new row
  const int b = blockIdx.x * blockDim.x + threadIdx.x;  // new column
  if (b > a || b >= 3 * m) return;
  const int i = a / 3, ra = a % 3, j = b / 3, rb = b % 3;
  const T* gi = G + 18 * i + 6 * ra;
  const T* gj = G + 18 * j + 6 * rb;
  double acc = 0;
  for (int c = 0; c < 6; ++c) {
    double t = 0;
    for (int d = 0; d < 6; ++d) t += c66[c + 6 * d] * gj[d];
    acc += gi[c] * t;
  }
  if (i == j) acc += Nz[9 * i + 3 * ra + rb];
  C[n_old + a + static_cast<std::size_t>(n_old + b) * ld] = static_cast<T>(acc);
}

template <typename T>
__global__ void zeroStrictUpperKernel(T* __restrict__ M, int n) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  for (int j = blockIdx.y; j < n; j += gridDim.y)
    if (i < j) M[i + static_cast<std::size_t>(j) * n] = T(0);
}

// One thread per (moved row, target column j): see launchFillHoles in
// kernels.cuh for why reading and writing the same matrix is safe. Threads of
// a warp take consecutive j: the writes of the column part (j >= D) are
// coalesced, the other writes and most reads (the source rows lie below, so
// they are read across columns) are strided. At most 60 rows x n elements per
// iteration: the whole removal is 0.14 ms at K = 8000 (docs/BENCHMARKS.md).
template <typename T>
__global__ void fillHolesKernel(T* __restrict__ C, std::size_t ld, int n_new, int pose_dim,
                                const int* __restrict__ old_slot, const int* __restrict__ holes) {
  const int j = blockIdx.x * blockDim.x + threadIdx.x;
  if (j >= n_new) return;
  const int P = pose_dim;
  const int t = blockIdx.y / 3, r = blockIdx.y % 3;
  const int hole = holes[t];
  const int D = landmarkRowDev(hole, P) + r;
  const int S = landmarkRowDev(old_slot[hole], P) + r;
  const int m = j < P ? j : landmarkRowDev(old_slot[(j - P) / 3], P) + (j - P) % 3;
  const T v = C[static_cast<std::size_t>(max(S, m)) + static_cast<std::size_t>(min(S, m)) * ld];
  C[static_cast<std::size_t>(max(D, j)) + static_cast<std::size_t>(min(D, j)) * ld] = v;
}

inline unsigned blocksFor(long long count) { return static_cast<unsigned>((count + kThreads - 1) / kThreads); }

template <typename T, int P>
cudaError_t launchPredictP(T* C, std::size_t ld, int n, const double* F, const double* Q, cudaStream_t stream) {
  // Cross rows first (they read only rows >= P), then the pose block.
  if (n > P) {
    predictCrossKernel<T, P><<<blocksFor(n - P), kThreads, 0, stream>>>(C, ld, n, F);
    const cudaError_t e = cudaGetLastError();
    if (e != cudaSuccess) return e;
  }
  predictPoseKernel<T, P><<<1, P * P, 0, stream>>>(C, ld, F, Q);
  return cudaGetLastError();
}

}  // namespace

template <typename T>
cudaError_t launchGatherPHt(const T* C, std::size_t ld, int n, int pose_dim, const int* slots, const T* H, int m,
                            T* P, std::size_t ldP, cudaStream_t stream) {
  if (n <= 0 || m <= 0) return cudaSuccess;
  gatherPHtKernel<T><<<dim3(blocksFor(n), m), kThreads, 0, stream>>>(C, ld, n, pose_dim, slots, H, P, ldP);
  const cudaError_t e = cudaGetLastError();
  if (e != cudaSuccess) return e;
  gatherUpperKernel<T><<<dim3((n + kTile - 1) / kTile, (m + kTile - 1) / kTile), dim3(kTile, kTileRows), 0, stream>>>(
      C, ld, n, pose_dim, slots, H, m, P, ldP);
  return cudaGetLastError();
}

template <typename T>
cudaError_t launchInnovationCov(const T* P, std::size_t ldP, int pose_dim, const int* slots, const T* H, const T* R,
                                int m, T* S, cudaStream_t stream) {
  if (m <= 0) return cudaSuccess;
  innovationCovKernel<T><<<dim3(blocksFor(3 * m), 3 * m), kThreads, 0, stream>>>(P, ldP, pose_dim, slots, H, R, m,
                                                                                   S);
  return cudaGetLastError();
}

template <typename T>
cudaError_t launchCountNonFinite(const T* x, std::size_t count, int* flag, cudaStream_t stream) {
  if (count == 0) return cudaSuccess;
  nonFiniteKernel<T><<<blocksFor(static_cast<long long>(count)), kThreads, 0, stream>>>(x, count, flag);
  return cudaGetLastError();
}

template <typename T>
cudaError_t launchPredict(T* C, std::size_t ld, int n, int pose_dim, const double* F, const double* Q,
                          cudaStream_t stream) {
  // The pose block sizes of the motion models (types.hpp: 12, 15, 18, the
  // inertial model's calibration rows 19, 24, 25, each + 6 with the frame
  // error), unrolled each; P * P <= 1024 threads of one block.
  if (pose_dim == 12) return launchPredictP<T, 12>(C, ld, n, F, Q, stream);
  if (pose_dim == 15) return launchPredictP<T, 15>(C, ld, n, F, Q, stream);
  if (pose_dim == 18) return launchPredictP<T, 18>(C, ld, n, F, Q, stream);
  if (pose_dim == 21) return launchPredictP<T, 21>(C, ld, n, F, Q, stream);
  if (pose_dim == 24) return launchPredictP<T, 24>(C, ld, n, F, Q, stream);
  if (pose_dim == 19) return launchPredictP<T, 19>(C, ld, n, F, Q, stream);
  if (pose_dim == 25) return launchPredictP<T, 25>(C, ld, n, F, Q, stream);
  if (pose_dim == 30) return launchPredictP<T, 30>(C, ld, n, F, Q, stream);
  if (pose_dim == 31) return launchPredictP<T, 31>(C, ld, n, F, Q, stream);
  return cudaErrorInvalidValue;
}

template <typename T>
cudaError_t launchMarginals(const T* C, std::size_t ld, int pose_dim, const int* slots, int count, double* out,
                            cudaStream_t stream) {
  if (count <= 0) return cudaSuccess;
  marginalsKernel<T><<<count, 81, 0, stream>>>(C, ld, pose_dim, slots, out);
  return cudaGetLastError();
}

template <typename T>
cudaError_t launchLandmarkBlocks(const T* C, std::size_t ld, int pose_dim, int K, double* out, cudaStream_t stream) {
  if (K <= 0) return cudaSuccess;
  landmarkBlocksKernel<T><<<blocksFor(K), kThreads, 0, stream>>>(C, ld, pose_dim, K, out);
  return cudaGetLastError();
}

template <typename T>
cudaError_t launchAddLandmarks(T* C, std::size_t ld, int n_old, const T* G, const T* Nz, int m,
                               cudaStream_t stream) {
  if (m <= 0) return cudaSuccess;
  // Both kernels read only the pose rows/columns 0..5 and write rows >= n_old.
  addCrossKernel<T><<<blocksFor(n_old), kThreads, 0, stream>>>(C, ld, n_old, G, m);
  cudaError_t e = cudaGetLastError();
  if (e != cudaSuccess) return e;
  addNewNewKernel<T><<<dim3(blocksFor(3 * m), 3 * m), kThreads, 0, stream>>>(C, ld, n_old, G, Nz, m);
  return cudaGetLastError();
}

template <typename T>
cudaError_t launchZeroStrictUpper(T* M, int n, cudaStream_t stream) {
  if (n <= 1) return cudaSuccess;
  zeroStrictUpperKernel<T><<<dim3(blocksFor(n), n < 65535 ? n : 65535), kThreads, 0, stream>>>(M, n);
  return cudaGetLastError();
}

template <typename T>
cudaError_t launchFillHoles(T* C, std::size_t ld, int n_new, int pose_dim, const int* old_slot_of_new,
                            const int* holes, int h, cudaStream_t stream) {
  constexpr int kMaxHoles = 65535 / 3;  // gridDim.y limit
  for (int t0 = 0; t0 < h && n_new > 0; t0 += kMaxHoles) {
    const int count = h - t0 < kMaxHoles ? h - t0 : kMaxHoles;
    const dim3 grid(blocksFor(n_new), static_cast<unsigned>(3 * count));
    fillHolesKernel<T><<<grid, kThreads, 0, stream>>>(C, ld, n_new, pose_dim, old_slot_of_new, holes + t0);
    const cudaError_t e = cudaGetLastError();
    if (e != cudaSuccess) return e;
  }
  return cudaSuccess;
}

#define HAPI_INSTANTIATE(T)                                                                                          \
  template cudaError_t launchGatherPHt<T>(const T*, std::size_t, int, int, const int*, const T*, int, T*,              \
                                          std::size_t, cudaStream_t);                                                \
  template cudaError_t launchInnovationCov<T>(const T*, std::size_t, int, const int*, const T*, const T*, int, T*,    \
                                              cudaStream_t);                                                         \
  template cudaError_t launchCountNonFinite<T>(const T*, std::size_t, int*, cudaStream_t);                         \
  template cudaError_t launchPredict<T>(T*, std::size_t, int, int, const double*, const double*, cudaStream_t);      \
  template cudaError_t launchMarginals<T>(const T*, std::size_t, int, const int*, int, double*, cudaStream_t);        \
  template cudaError_t launchLandmarkBlocks<T>(const T*, std::size_t, int, int, double*, cudaStream_t);               \
  template cudaError_t launchAddLandmarks<T>(T*, std::size_t, int, const T*, const T*, int, cudaStream_t);            \
  template cudaError_t launchZeroStrictUpper<T>(T*, int, cudaStream_t);                                            \
  template cudaError_t launchFillHoles<T>(T*, std::size_t, int, int, const int*, const int*, int, cudaStream_t);
HAPI_INSTANTIATE(double)
HAPI_INSTANTIATE(float)
#undef HAPI_INSTANTIATE

}  // namespace cuda
}  // namespace hapi_eskf
