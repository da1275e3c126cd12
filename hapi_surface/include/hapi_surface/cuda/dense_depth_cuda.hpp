// The block matcher (dense_depth_block_match.hpp) on a CUDA device: one
// thread per left pixel running the shared per-pixel rule. Built only with
// CUDA (HAPI_SURFACE_WITH_CUDA).
#pragma once

#include "hapi_surface/dense_depth_block_match.hpp"

#include <cstdint>

namespace hapi_surface {

// Whether a CUDA device can be used now.
bool denseDepthCudaDevice();

// As blockMatchCpu, on the device (synchronous). Throws std::runtime_error
// on a CUDA error.
void blockMatchCuda(const std::uint8_t* left, const std::uint8_t* right, int w, int h, int stride,
                    const BlockMatchParams& p, float* disparity);

}  // namespace hapi_surface
