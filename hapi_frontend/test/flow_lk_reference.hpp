// The CUDA image-flow stage's work done on the host with the same functions
// (flow_lk_math.hpp), OpenCV-free: a window's pyramid, its corners, and
// tracks forward and back, as FlowLkCuda computes them. Used to check the
// functions against OpenCV (test_flow_lk_math.cpp) and the kernels against
// the functions (test/gpu/test_flow_lk_cuda.cpp).
#pragma once

#include "hapi_frontend/cuda/flow_lk_math.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace hapi_frontend {
namespace flow_lk_reference {

struct Pyramid {
  std::vector<std::vector<std::uint8_t>> img;
  std::vector<std::vector<std::int16_t>> deriv;  // dx, dy interleaved
  std::vector<flow_lk::Level> levels;
};

// pixels: w x h, row-major, stride w.
inline Pyramid build(const std::uint8_t* pixels, int w, int h, int window, int levels) {
  Pyramid p;
  const int n = flow_lk::pyramidLevels(w, h, window, levels);
  std::vector<int> ws{w}, hs{h};
  p.img.emplace_back(pixels, pixels + static_cast<std::size_t>(w) * h);
  for (int l = 1; l < n; ++l) {
    const int sw = ws.back(), sh = hs.back(), dw = (sw + 1) / 2, dh = (sh + 1) / 2;
    std::vector<std::uint8_t> d(static_cast<std::size_t>(dw) * dh);
    for (int y = 0; y < dh; ++y)
      for (int x = 0; x < dw; ++x) d[y * dw + x] = flow_lk::pyrDownAt(p.img.back().data(), sw, sh, x, y);
    p.img.push_back(std::move(d));
    ws.push_back(dw);
    hs.push_back(dh);
  }
  for (int l = 0; l < n; ++l) {
    std::vector<std::int16_t> d(2 * p.img[l].size());
    for (int y = 0; y < hs[l]; ++y)
      for (int x = 0; x < ws[l]; ++x) {
        std::int16_t* o = d.data() + 2 * (y * ws[l] + x);
        flow_lk::scharrAt(p.img[l].data(), ws[l], hs[l], x, y, o, o + 1);
      }
    p.deriv.push_back(std::move(d));
  }
  for (int l = 0; l < n; ++l) p.levels.push_back(flow_lk::Level{p.img[l].data(), p.deriv[l].data(), ws[l], hs[l]});
  return p;
}

// The minimum-eigenvalue map of the square [sx, sx + sw) x [sy, sy + sh).
inline std::vector<float> eigenMap(const std::uint8_t* pixels, int w, int h, int sx, int sy, int sw, int sh) {
  std::vector<float> eig(static_cast<std::size_t>(sw) * sh);
  for (int y = 0; y < sh; ++y)
    for (int x = 0; x < sw; ++x) eig[y * sw + x] = flow_lk::minEigenAt(pixels, w, h, sx, sy, sw, sh, x, y);
  return eig;
}

// The square's corners, x, y interleaved, in window coordinates.
inline std::vector<float> corners(const std::uint8_t* pixels, int w, int h, int sx, int sy, int sw, int sh,
                                  int max_features, double quality, double min_distance) {
  const std::vector<float> eig = eigenMap(pixels, w, h, sx, sy, sw, sh);
  float max = 0;
  for (float v : eig) max = std::max(max, v);
  const float threshold = static_cast<float>(static_cast<double>(max) * quality);
  std::vector<flow_lk::Candidate> cand;
  for (int y = 0; y < sh; ++y)
    for (int x = 0; x < sw; ++x)
      if (flow_lk::isCandidate(eig.data(), sw, sh, x, y, threshold)) cand.push_back({eig[y * sw + x], y * sw + x});
  std::vector<float> xy;
  flow_lk::selectCorners(&cand, sw, max_features, min_distance, &xy);
  for (std::size_t k = 0; k < xy.size(); k += 2) {
    xy[k] += static_cast<float>(sx);
    xy[k + 1] += static_cast<float>(sy);
  }
  return xy;
}

// One point from `from` to `to` (pyramids of equal level counts); *x, *y: the
// guess (with use_guess) and the result.
inline bool track(const Pyramid& from, const Pyramid& to, const flow_lk::LkSettings& s, float fx, float fy,
                  bool use_guess, float* x, float* y) {
  std::vector<std::int16_t> scratch(3 * static_cast<std::size_t>(s.window) * s.window);
  return flow_lk::trackPoint(flow_lk::SoloTeam(), from.levels.data(), to.levels.data(), s, fx, fy, use_guess, x, y,
                             scratch.data());
}

}  // namespace flow_lk_reference
}  // namespace hapi_frontend
