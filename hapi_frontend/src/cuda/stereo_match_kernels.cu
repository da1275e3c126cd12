// Stereo matching kernels. The geometric test is evaluated per pair with the
// exact operation order of stereo_match_core.cpp and every double operation
// rounded on its own (__dmul_rn/__dadd_rn: no FMA contraction), so the
// candidate sets of the CPU and the GPU are identical; distances are integer
// popcounts and ties are broken by index, hence the whole result is exact.
#include "stereo_match_kernels.cuh"

#include "cuda_check.hpp"

#include <climits>

namespace hapi_frontend {
namespace match_cuda {

namespace {

constexpr int kTile = 32;        // right columns per block (threadIdx.x)
constexpr int kRowsPerBlock = 32;  // left rows per block in the column pass
constexpr int kMaxWords = 32;    // descriptors up to 128 bytes

// Epipolar line of a left point and its squared acceptance bound.
struct Line {
  double l0, l1, l2, lim;
};

__device__ __forceinline__ Line epiline(const MatchGeometry& g, double xl, double yl) {
  Line L;
  L.l0 = __dadd_rn(__dadd_rn(__dmul_rn(g.F[0], xl), __dmul_rn(g.F[1], yl)), g.F[2]);
  L.l1 = __dadd_rn(__dadd_rn(__dmul_rn(g.F[3], xl), __dmul_rn(g.F[4], yl)), g.F[5]);
  L.l2 = __dadd_rn(__dadd_rn(__dmul_rn(g.F[6], xl), __dmul_rn(g.F[7], yl)), g.F[8]);
  L.lim = __dmul_rn(g.max_e2, __dadd_rn(__dmul_rn(L.l0, L.l0), __dmul_rn(L.l1, L.l1)));
  return L;
}

__device__ __forceinline__ bool candidate(const MatchGeometry& g, const Line& L, double xl, double xr, double yr) {
  const double disp = __dadd_rn(xl, -xr);
  if (disp < g.min_disparity || disp > g.max_disparity) return false;
  const double e = __dadd_rn(__dadd_rn(__dmul_rn(L.l0, xr), __dmul_rn(L.l1, yr)), L.l2);
  return !(__dmul_rn(e, e) > L.lim);
}

__device__ __forceinline__ int hamming(const uint32_t* a, const uint32_t* b, int words) {
  int d = 0;
  for (int k = 0; k < words; ++k) d += __popc(a[k] ^ b[k]);
  return d;
}

// Block (32 x 8): tile of 32 right columns x 32 left rows; each thread scans 4
// rows of its column, the block reduces per column, one atomicMin per column.
__global__ void columnBestKernel(const uint32_t* __restrict__ desc_l, const float* __restrict__ pts_l, int n_l,
                                 const uint32_t* __restrict__ desc_r, const float* __restrict__ pts_r, int n_r,
                                 int words, MatchGeometry g, unsigned long long* __restrict__ col_best) {
  extern __shared__ uint32_t sh[];
  uint32_t* sl = sh;                       // kRowsPerBlock * words
  __shared__ unsigned long long red[8][kTile];
  const int j = blockIdx.x * kTile + threadIdx.x;
  const int i0 = blockIdx.y * kRowsPerBlock;
  const int tid = threadIdx.y * kTile + threadIdx.x;
  for (int k = tid; k < kRowsPerBlock * words; k += kTile * 8) {
    const int r = i0 + k / words;
    sl[k] = r < n_l ? desc_l[static_cast<size_t>(r) * words + k % words] : 0u;
  }
  __syncthreads();
  unsigned long long best = ULLONG_MAX;
  if (j < n_r) {
    uint32_t dr[kMaxWords];
    for (int k = 0; k < words; ++k) dr[k] = desc_r[static_cast<size_t>(j) * words + k];
    const double xr = pts_r[2 * j], yr = pts_r[2 * j + 1];
    for (int r = threadIdx.y; r < kRowsPerBlock; r += 8) {
      const int i = i0 + r;
      if (i >= n_l) break;
      const double xl = pts_l[2 * i], yl = pts_l[2 * i + 1];
      const Line L = epiline(g, xl, yl);
      if (!candidate(g, L, xl, xr, yr)) continue;
      int d = 0;
      for (int k = 0; k < words; ++k) d += __popc(sl[r * words + k] ^ dr[k]);
      const unsigned long long key = (static_cast<unsigned long long>(d) << 32) | static_cast<unsigned>(i);
      best = min(best, key);
    }
  }
  red[threadIdx.y][threadIdx.x] = best;
  __syncthreads();
  if (threadIdx.y == 0 && j < n_r) {
    for (int y = 1; y < 8; ++y) best = min(best, red[y][threadIdx.x]);
    if (best != ULLONG_MAX) atomicMin(col_best + j, best);
  }
}

// Best = smallest (d, j); second = smallest d among the others.
struct BestSecond {
  int b, bj, s;
};

__device__ __forceinline__ BestSecond merge(const BestSecond& A, const BestSecond& B) {
  BestSecond r;
  if (A.b < B.b || (A.b == B.b && A.bj < B.bj)) {
    r.b = A.b;
    r.bj = A.bj;
    r.s = min(A.s, B.b);
  } else {
    r.b = B.b;
    r.bj = B.bj;
    r.s = min(B.s, A.b);
  }
  return r;
}

// One warp per left keypoint; lane scans j = lane, lane + 32, ... (ascending,
// strict '<' keeps the smallest j of its share), then a warp merge.
__global__ void rowDecideKernel(const uint32_t* __restrict__ desc_l, const float* __restrict__ pts_l, int n_l,
                                const uint32_t* __restrict__ desc_r, const float* __restrict__ pts_r, int n_r,
                                int words, MatchGeometry g, const unsigned long long* __restrict__ col_best,
                                int* __restrict__ out_j, int* __restrict__ out_d) {
  const int i = static_cast<int>((blockIdx.x * blockDim.x + threadIdx.x) >> 5);
  const int lane = threadIdx.x & 31;
  if (i >= n_l) return;  // uniform per warp
  uint32_t dl[kMaxWords];
  for (int k = 0; k < words; ++k) dl[k] = desc_l[static_cast<size_t>(i) * words + k];
  const double xl = pts_l[2 * i], yl = pts_l[2 * i + 1];
  const Line L = epiline(g, xl, yl);
  BestSecond bs{INT_MAX, INT_MAX, INT_MAX};
  for (int j = lane; j < n_r; j += 32) {
    if (!candidate(g, L, xl, pts_r[2 * j], pts_r[2 * j + 1])) continue;
    const int d = hamming(dl, desc_r + static_cast<size_t>(j) * words, words);
    if (d < bs.b) {
      bs.s = bs.b;
      bs.b = d;
      bs.bj = j;
    } else if (d < bs.s) {
      bs.s = d;
    }
  }
#pragma unroll
  for (int o = 16; o > 0; o >>= 1) {
    BestSecond other;
    other.b = __shfl_down_sync(0xffffffffu, bs.b, o);
    other.bj = __shfl_down_sync(0xffffffffu, bs.bj, o);
    other.s = __shfl_down_sync(0xffffffffu, bs.s, o);
    bs = merge(bs, other);
  }
  if (lane != 0) return;
  int mj = -1;
  if (bs.bj != INT_MAX && bs.b <= g.max_hamming) {
    const bool ratio_ok = bs.s == INT_MAX || static_cast<double>(bs.b) < __dmul_rn(g.ratio, static_cast<double>(bs.s));
    const bool cross_ok = !g.cross_check || static_cast<int>(col_best[bs.bj] & 0xFFFFFFFFull) == i;
    if (ratio_ok && cross_ok) mj = bs.bj;
  }
  out_j[i] = mj;
  out_d[i] = mj >= 0 ? bs.b : 0;
}

}  // namespace

void launchColumnBest(const uint32_t* desc_l, const float* pts_l, int n_l, const uint32_t* desc_r, const float* pts_r,
                      int n_r, int words, const MatchGeometry& g, unsigned long long* col_best, cudaStream_t s) {
  const dim3 block(kTile, 8);
  const dim3 grid((n_r + kTile - 1) / kTile, (n_l + kRowsPerBlock - 1) / kRowsPerBlock);
  const size_t shm = static_cast<size_t>(kRowsPerBlock) * words * sizeof(uint32_t);
  columnBestKernel<<<grid, block, shm, s>>>(desc_l, pts_l, n_l, desc_r, pts_r, n_r, words, g, col_best);
  HAPI_CUDA_CHECK(cudaGetLastError());
}

void launchRowDecide(const uint32_t* desc_l, const float* pts_l, int n_l, const uint32_t* desc_r, const float* pts_r,
                     int n_r, int words, const MatchGeometry& g, const unsigned long long* col_best, int* out_j,
                     int* out_d, cudaStream_t s) {
  const int threads = 256;
  const int blocks = static_cast<int>((static_cast<long long>(n_l) * 32 + threads - 1) / threads);
  rowDecideKernel<<<blocks, threads, 0, s>>>(desc_l, pts_l, n_l, desc_r, pts_r, n_r, words, g, col_best, out_j, out_d);
  HAPI_CUDA_CHECK(cudaGetLastError());
}

}  // namespace match_cuda
}  // namespace hapi_frontend
