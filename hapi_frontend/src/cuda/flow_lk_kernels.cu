// The image-flow kernels (flow_lk_kernels.cuh): thin parallel loops over
// flow_lk_math.hpp.
#include "flow_lk_kernels.cuh"

#include "cuda_check.hpp"

namespace hapi_frontend {
namespace flow_lk_cuda {
namespace {

using flow_lk::Level;
using flow_lk::LkSettings;

constexpr int kWarp = 32;
constexpr int kWarpsPerBlock = 4;

dim3 gridFor(int w, int h, dim3 block) { return dim3((w + block.x - 1) / block.x, (h + block.y - 1) / block.y); }

__global__ void pyrDownKernel(const std::uint8_t* src, int sw, int sh, std::uint8_t* dst, int w, int h) {
  const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
  if (x < w && y < h) dst[y * w + x] = flow_lk::pyrDownAt(src, sw, sh, x, y);
}

__global__ void scharrKernel(const std::uint8_t* img, int w, int h, std::int16_t* deriv) {
  const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
  if (x < w && y < h) flow_lk::scharrAt(img, w, h, x, y, deriv + 2 * (y * w + x), deriv + 2 * (y * w + x) + 1);
}

__global__ void minEigenKernel(const std::uint8_t* img, int w, int h, int sx, int sy, int sw, int sh, float* eig,
                               unsigned int* max_bits) {
  const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
  if (x >= sw || y >= sh) return;
  const float v = flow_lk::minEigenAt(img, w, h, sx, sy, sw, sh, x, y);
  eig[y * sw + x] = v;
  // Rounding can make a flat pixel's value slightly negative: it never is
  // the maximum that matters, and 0 keeps the integer order valid.
  atomicMax(max_bits, __float_as_uint(fmaxf(v, 0.f)));
}

__global__ void candidatesKernel(const float* eig, int sw, int sh, const unsigned int* max_bits, double quality,
                                 flow_lk::Candidate* out, int* count) {
  const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
  if (x >= sw || y >= sh) return;
  const float threshold = static_cast<float>(static_cast<double>(__uint_as_float(*max_bits)) * quality);
  if (!flow_lk::isCandidate(eig, sw, sh, x, y, threshold)) return;
  const int k = atomicAdd(count, 1);
  out[k] = flow_lk::Candidate{eig[y * sw + x], y * sw + x};
}

// The team of flow_lk::trackPoint on the device: the 32 lanes of a warp; the
// sum is exact (int64), so its order does not matter.
// (Host-device members, as trackPoint is: only the device code runs.)
struct WarpTeam {
  int lane;
  __host__ __device__ int rank() const { return lane; }
  __host__ __device__ int size() const { return kWarp; }
  __host__ __device__ long long sum(long long v) const {
#ifdef __CUDA_ARCH__
    for (int o = kWarp / 2; o > 0; o >>= 1) v += __shfl_xor_sync(0xffffffffu, v, o);
#endif
    return v;
  }
};

__global__ void trackKernel(const Level* prev, const Level* next, LkSettings settings, const float* from, float* to,
                            bool guess, std::uint8_t* ok, int n, std::int16_t* scratch) {
  const int point = blockIdx.x * kWarpsPerBlock + threadIdx.x / kWarp;
  if (point >= n) return;  // whole warps leave together
  const WarpTeam team{static_cast<int>(threadIdx.x % kWarp)};
  float tx = guess ? to[2 * point] : 0.f, ty = guess ? to[2 * point + 1] : 0.f;
  const int area = settings.window * settings.window;
  const bool status = flow_lk::trackPoint(team, prev, next, settings, from[2 * point], from[2 * point + 1], guess,
                                          &tx, &ty, scratch + static_cast<size_t>(point) * 3 * area);
  if (team.lane == 0) {
    to[2 * point] = tx;
    to[2 * point + 1] = ty;
    ok[point] = status ? 1 : 0;
  }
}

}  // namespace

void launchPyrDown(const std::uint8_t* src, int sw, int sh, std::uint8_t* dst, int w, int h, cudaStream_t s) {
  const dim3 block(32, 8);
  pyrDownKernel<<<gridFor(w, h, block), block, 0, s>>>(src, sw, sh, dst, w, h);
  HAPI_CUDA_CHECK(cudaGetLastError());
}

void launchScharr(const std::uint8_t* img, int w, int h, std::int16_t* deriv, cudaStream_t s) {
  const dim3 block(32, 8);
  scharrKernel<<<gridFor(w, h, block), block, 0, s>>>(img, w, h, deriv);
  HAPI_CUDA_CHECK(cudaGetLastError());
}

void launchMinEigen(const std::uint8_t* img, int w, int h, int sx, int sy, int sw, int sh, float* eig,
                    unsigned int* max_bits, cudaStream_t s) {
  const dim3 block(32, 8);
  minEigenKernel<<<gridFor(sw, sh, block), block, 0, s>>>(img, w, h, sx, sy, sw, sh, eig, max_bits);
  HAPI_CUDA_CHECK(cudaGetLastError());
}

void launchCandidates(const float* eig, int sw, int sh, const unsigned int* max_bits, double quality,
                      flow_lk::Candidate* out, int* count, cudaStream_t s) {
  const dim3 block(32, 8);
  candidatesKernel<<<gridFor(sw, sh, block), block, 0, s>>>(eig, sw, sh, max_bits, quality, out, count);
  HAPI_CUDA_CHECK(cudaGetLastError());
}

void launchTrack(const Level* prev, const Level* next, const LkSettings& settings, const float* from, float* to,
                 bool guess, std::uint8_t* ok, int n, std::int16_t* scratch, cudaStream_t s) {
  if (n <= 0) return;
  const int blocks = (n + kWarpsPerBlock - 1) / kWarpsPerBlock;
  trackKernel<<<blocks, kWarpsPerBlock * kWarp, 0, s>>>(prev, next, settings, from, to, guess, ok, n, scratch);
  HAPI_CUDA_CHECK(cudaGetLastError());
}

}  // namespace flow_lk_cuda
}  // namespace hapi_frontend
