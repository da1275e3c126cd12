// Internal: launchers of the ORB kernels (orb_kernels.cu). Each one mirrors
// one block of OrbCpuCore::extract (orb_core.cpp); the comments there define
// the arithmetic, the kernels only parallelise it.
#pragma once

#include <cuda_runtime.h>

#include <cstddef>
#include <cstdint>

namespace hapi_frontend {
namespace orb_cuda {

// Per-level view for the describe kernel.
struct LevelDev {
  const uint8_t* img = nullptr;     // level image (FAST, orientation)
  const uint8_t* smooth = nullptr;  // 5x5 binomial smoothed level (BRIEF tests)
  int width = 0, height = 0;
  int quota = 0;   // features kept on this level
  int qstart = 0;  // sum of the quotas of the levels before
};

// Raw keypoint as produced on the device (level coordinates).
struct KeypointDev {
  int lx, ly, level, score, angle_bin;
};

// Per-level key = (level << 48) | orb_rank_key(score, y, x): one radix sort
// orders all levels at once, level-major, rank order inside a level.
constexpr int kRankKeyBits = 48;

void launchResize(const uint8_t* src, int sw, int sh, uint8_t* dst, int w, int h, const int* xi, const int* xw,
                  const int* yi, const int* yw, cudaStream_t s);
void launchSmooth(const uint8_t* img, uint16_t* tmp, uint8_t* out, int w, int h, cudaStream_t s);
// FAST-9 score into `score` (w*h), then strict 3x3 NMS on [edge, w-edge) x
// [edge, h-edge): each local maximum appends its key to keys[0..) and
// increments *count.
void launchFastNms(const uint8_t* img, uint8_t* score, int w, int h, int threshold, int edge, int level,
                   unsigned long long* keys, int* count, cudaStream_t s);

std::size_t sortTempBytes(int n, int end_bit);
void launchSortKeys(void* temp, std::size_t temp_bytes, const unsigned long long* in, unsigned long long* out, int n,
                    int end_bit, cudaStream_t s);

// One warp per quota slot: orientation moments, angle bin, 256 BRIEF tests.
// counts[l] = candidates of level l; sorted = all keys sorted ascending.
void launchDescribe(const LevelDev* levels, int n_levels, const int* counts, const unsigned long long* sorted,
                    const int8_t* rotated_patterns, int quota_total, double rad2deg, KeypointDev* out_kp,
                    uint8_t* out_desc, cudaStream_t s);

}  // namespace orb_cuda
}  // namespace hapi_frontend
