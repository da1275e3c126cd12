// Association and descriptor bookkeeping kernels (docs/DESIGN.md "Gate each
// association": the descriptor stage that precedes the Mahalanobis gate).
#include "kernels.cuh"

#include <cstdint>

namespace hapi_eskf {
namespace cuda {
namespace {

constexpr int kMatchThreads = 256;
constexpr unsigned long long kNone = ~0ull;

// Candidates are ordered by the key (distance << 32 | slot): the smaller
// distance wins, and among equal distances the lower slot (the CPU
// reference scans slots in increasing order with strict '<').
__device__ __forceinline__ void insertTop2(unsigned long long key, unsigned long long* b1, unsigned long long* b2) {
  if (key < *b1) {
    *b2 = *b1;
    *b1 = key;
  } else if (key < *b2) {
    *b2 = key;
  }
}

__global__ void hammingTop2Kernel(const uint8_t* __restrict__ pool, int K, const uint8_t* __restrict__ queries, int D,
                                  int* best_slot, int* best_dist, int* second_slot, int* second_dist) {
  extern __shared__ uint8_t q[];
  __shared__ unsigned long long red1[kMatchThreads / 32], red2[kMatchThreads / 32];
  const int qi = blockIdx.x;
  for (int b = threadIdx.x; b < D; b += blockDim.x) q[b] = queries[static_cast<std::size_t>(qi) * D + b];
  __syncthreads();

  unsigned long long b1 = kNone, b2 = kNone;
  const bool words = (D % 4) == 0;
  for (int s = threadIdx.x; s < K; s += blockDim.x) {
    const uint8_t* d = pool + static_cast<std::size_t>(s) * D;
    int dist = 0;
    if (words) {
      const uint32_t* dw = reinterpret_cast<const uint32_t*>(d);
      const uint32_t* qw = reinterpret_cast<const uint32_t*>(q);
      for (int w = 0; w < D / 4; ++w) dist += __popc(dw[w] ^ qw[w]);
    } else {
      for (int b = 0; b < D; ++b) dist += __popc(static_cast<unsigned>(d[b] ^ q[b]));
    }
    insertTop2((static_cast<unsigned long long>(dist) << 32) | static_cast<unsigned>(s), &b1, &b2);
  }
  // Warp merge of top-2 lists, then across warps.
  for (int off = 16; off > 0; off >>= 1) {
    const unsigned long long o1 = __shfl_down_sync(0xffffffffu, b1, off);
    const unsigned long long o2 = __shfl_down_sync(0xffffffffu, b2, off);
    insertTop2(o1, &b1, &b2);
    insertTop2(o2, &b1, &b2);
  }
  const int warp = threadIdx.x / 32, lane = threadIdx.x % 32;
  if (lane == 0) {
    red1[warp] = b1;
    red2[warp] = b2;
  }
  __syncthreads();
  if (threadIdx.x == 0) {
    unsigned long long t1 = kNone, t2 = kNone;
    for (int w = 0; w < static_cast<int>(blockDim.x / 32); ++w) {
      insertTop2(red1[w], &t1, &t2);
      insertTop2(red2[w], &t1, &t2);
    }
    best_slot[qi] = t1 == kNone ? -1 : static_cast<int>(t1 & 0xffffffffu);
    best_dist[qi] = t1 == kNone ? (1 << 30) : static_cast<int>(t1 >> 32);
    second_slot[qi] = t2 == kNone ? -1 : static_cast<int>(t2 & 0xffffffffu);
    second_dist[qi] = t2 == kNone ? (1 << 30) : static_cast<int>(t2 >> 32);
  }
}

__global__ void gatherDescriptorsKernel(const uint8_t* __restrict__ src, const int* __restrict__ keep, int count,
                                        int D, uint8_t* __restrict__ dst) {
  const long long t = static_cast<long long>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (t >= static_cast<long long>(count) * D) return;
  const int k = static_cast<int>(t / D), b = static_cast<int>(t % D);
  dst[t] = src[static_cast<std::size_t>(keep[k]) * D + b];
}

}  // namespace

cudaError_t launchHammingTop2(const uint8_t* pool, int K, const uint8_t* queries, int n_query, int D,
                              int* best_slot, int* best_dist, int* second_slot, int* second_dist,
                              cudaStream_t stream) {
  if (n_query <= 0) return cudaSuccess;
  hammingTop2Kernel<<<n_query, kMatchThreads, D, stream>>>(pool, K, queries, D, best_slot, best_dist, second_slot,
                                                           second_dist);
  return cudaGetLastError();
}

cudaError_t launchGatherDescriptors(const uint8_t* src, const int* keep, int count, int D, uint8_t* dst,
                                    cudaStream_t stream) {
  const long long total = static_cast<long long>(count) * D;
  if (total <= 0) return cudaSuccess;
  gatherDescriptorsKernel<<<static_cast<unsigned>((total + 255) / 256), 256, 0, stream>>>(src, keep, count, D, dst);
  return cudaGetLastError();
}

}  // namespace cuda
}  // namespace hapi_eskf
