// Internal: launchers of the image-flow kernels (flow_lk_kernels.cu). Each
// applies one function of flow_lk_math.hpp to every pixel or point; the
// arithmetic is defined there.
#pragma once

#include "hapi_frontend/cuda/flow_lk_math.hpp"

#include <cuda_runtime.h>

#include <cstdint>

namespace hapi_frontend {
namespace flow_lk_cuda {

// dst (w x h) = pyrDown of src (sw x sh).
void launchPyrDown(const std::uint8_t* src, int sw, int sh, std::uint8_t* dst, int w, int h, cudaStream_t s);
// deriv (2 int16 per pixel) = Scharr dx, dy of img (w x h).
void launchScharr(const std::uint8_t* img, int w, int h, std::int16_t* deriv, cudaStream_t s);
// eig (sw x sh) = minimum eigenvalue over the square at (sx, sy) of img;
// *max_bits = the largest value's bits (non-negative floats order as ints;
// the caller zeroes it).
void launchMinEigen(const std::uint8_t* img, int w, int h, int sx, int sy, int sw, int sh, float* eig,
                    unsigned int* max_bits, cudaStream_t s);
// Appends the candidates of eig (threshold = quality x the maximum) to
// out[0..), counting them in *count (the caller zeroes it).
void launchCandidates(const float* eig, int sw, int sh, const unsigned int* max_bits, double quality,
                      flow_lk::Candidate* out, int* count, cudaStream_t s);
// One warp per point: from[2 i..] tracked from prev to next (levels
// 0..settings.max_level each, device arrays); with guess, `to` holds the
// initial positions. ok[i] = status; scratch: 3 window areas per point.
void launchTrack(const flow_lk::Level* prev, const flow_lk::Level* next, const flow_lk::LkSettings& settings,
                 const float* from, float* to, bool guess, std::uint8_t* ok, int n, std::int16_t* scratch,
                 cudaStream_t s);

}  // namespace flow_lk_cuda
}  // namespace hapi_frontend
