// The arithmetic of the CUDA image-flow stage (flow_lk_cuda.hpp), written
// once for the kernels and for the host, which checks it against OpenCV 4.6
// (test_flow_lk_math.cpp): the LK pyramid (cv::pyrDown, border reflect-101,
// integer exact), the LK derivatives (OpenCV's Scharr of
// buildOpticalFlowPyramid, integer exact), the Shi-Tomasi minimum eigenvalue
// of goodFeaturesToTrack (3x3 Sobel, 3x3 block; float, to rounding) and one
// point's pyramidal Lucas-Kanade (calcOpticalFlowPyrLK: 14-bit bilinear
// weights, the same window, minimum-eigenvalue test, iterations and
// termination). The LK sums are integers added exactly (int64), so a warp's
// reduction and the host's loop give the same value. Plain C++, no CUDA
// header: HAPI_HD marks the functions both compilers build.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#if defined(__CUDACC__)
#define HAPI_HD __host__ __device__
#else
#define HAPI_HD
#endif

namespace hapi_frontend {
namespace flow_lk {

constexpr int kMaxLevels = 6;       // ImageFlowParams::pyramid_levels' range
constexpr int kMaxWindow = 61;      // ImageFlowParams::lk_window's range
constexpr float kMinEigThreshold = 1e-4f;  // calcOpticalFlowPyrLK's default

// One pyramid level on the device or the host: the image (row-major, pitch =
// width) and its Scharr derivatives (dx, dy interleaved).
struct Level {
  const std::uint8_t* img = nullptr;
  const std::int16_t* deriv = nullptr;
  int width = 0, height = 0;
};

// (Set from ImageFlowParams by FlowLkCuda.)
struct LkSettings {
  int window = 0;         // odd
  int max_level = 0;      // levels - 1 (already limited to the pyramid's)
  int iterations = 0;     // calcOpticalFlowPyrLK's cap of 100 applied
  double epsilon_sq = 0;  // [px^2] the update below which LK stops
};

// OpenCV's borderInterpolate for BORDER_REFLECT_101 (any distance).
HAPI_HD inline int reflect101(int p, int len) {
  if (len == 1) return 0;
  while (p < 0 || p >= len) p = p < 0 ? -p : 2 * len - 2 - p;
  return p;
}

// The number of LK levels buildOpticalFlowPyramid makes: a level is added
// only while both sides of the next stay larger than the window.
HAPI_HD inline int pyramidLevels(int width, int height, int window, int levels) {
  int n = 1;
  while (n < levels) {
    width = (width + 1) / 2;
    height = (height + 1) / 2;
    if (width <= window || height <= window) break;
    ++n;
  }
  return n;
}

// cv::pyrDown's pixel (x, y) of the level below `src` (sw x sh): 5x5
// binomial, reflect-101, (sum + 128) >> 8.
HAPI_HD inline std::uint8_t pyrDownAt(const std::uint8_t* src, int sw, int sh, int x, int y) {
  const int k[5] = {1, 4, 6, 4, 1};
  int sum = 0;
  for (int j = 0; j < 5; ++j) {
    const std::uint8_t* row = src + reflect101(2 * y + j - 2, sh) * sw;
    int r = 0;
    for (int i = 0; i < 5; ++i) r += k[i] * row[reflect101(2 * x + i - 2, sw)];
    sum += k[j] * r;
  }
  return static_cast<std::uint8_t>((sum + 128) >> 8);
}

// OpenCV's calcSharrDeriv at (x, y): dx, dy (3 10 3 smoothing), reflect-101.
HAPI_HD inline void scharrAt(const std::uint8_t* img, int w, int h, int x, int y, std::int16_t* dx, std::int16_t* dy) {
  const int y0 = reflect101(y - 1, h), y2 = reflect101(y + 1, h);
  int t0[3], t1[3];
  for (int i = 0; i < 3; ++i) {
    const int xx = reflect101(x + i - 1, w);
    t0[i] = (img[y0 * w + xx] + img[y2 * w + xx]) * 3 + img[y * w + xx] * 10;
    t1[i] = img[y2 * w + xx] - img[y0 * w + xx];
  }
  *dx = static_cast<std::int16_t>(t0[2] - t0[0]);
  *dy = static_cast<std::int16_t>((t1[2] + t1[0]) * 3 + t1[1] * 10);
}

// cornerMinEigenVal (block 3, Sobel 3) at (x, y) of the search square
// [sx, sx + sw) x [sy, sy + sh) of `img` (w x h): the Sobel derivatives see
// the image about the square (OpenCV filters a ROI with its surroundings,
// reflect-101 only at the image's edge), the 3x3 block sum reflects at the
// square's edge (goodFeaturesToTrack filters a fresh matrix).
HAPI_HD inline float minEigenAt(const std::uint8_t* img, int w, int h, int sx, int sy, int sw, int sh, int x, int y) {
  const float scale = static_cast<float>(1.0 / (4.0 * 3.0 * 255.0));
  float cxx = 0, cxy = 0, cyy = 0;
  for (int j = -1; j <= 1; ++j)
    for (int i = -1; i <= 1; ++i) {
      const int px = sx + reflect101(x + i, sw), py = sy + reflect101(y + j, sh);
      int gx = 0, gy = 0;
      const int ks[3] = {1, 2, 1};
      for (int k = 0; k < 3; ++k) {
        const int ry = reflect101(py + k - 1, h), rx = reflect101(px + k - 1, w);
        gx += ks[k] * (img[ry * w + reflect101(px + 1, w)] - img[ry * w + reflect101(px - 1, w)]);
        gy += ks[k] * (img[reflect101(py + 1, h) * w + rx] - img[reflect101(py - 1, h) * w + rx]);
      }
      const float fx = gx * scale, fy = gy * scale;
      cxx += fx * fx;
      cxy += fx * fy;
      cyy += fy * fy;
    }
  const float a = cxx * 0.5f, b = cxy, c = cyy * 0.5f;
  return (a + c) - std::sqrt((a - c) * (a - c) + b * b);
}

// goodFeaturesToTrack's candidate test at (x, y) of the eigenvalue map of
// the square (sw x sh): inside the 1-pixel frame, above `threshold` (the
// strongest's fraction) and not below any of its 8 neighbours after values
// not above the threshold became 0 (threshold TOZERO + 3x3 dilate).
HAPI_HD inline bool isCandidate(const float* eig, int sw, int sh, int x, int y, float threshold) {
  if (x < 1 || y < 1 || x > sw - 2 || y > sh - 2) return false;
  const float v = eig[y * sw + x];
  if (!(v > threshold)) return false;
  for (int j = -1; j <= 1; ++j)
    for (int i = -1; i <= 1; ++i) {
      const float n = eig[(y + j) * sw + x + i];
      if (n > threshold && n > v) return false;
    }
  return true;
}

// cvRound of a float (round half to even, as lrintf in the default mode).
HAPI_HD inline int roundHalfEven(float v) {
  const float f = std::floor(v);
  const float d = v - f;
  int r = static_cast<int>(f);
  if (d > 0.5f || (d == 0.5f && (r & 1))) ++r;
  return r;
}

HAPI_HD inline int descale(int v, int n) { return (v + (1 << (n - 1))) >> n; }

// The fixed-point bilinear weights of calcOpticalFlowPyrLK (14 bits).
struct Weights {
  int w00, w01, w10, w11;
};
HAPI_HD inline Weights weightsFor(float a, float b) {
  constexpr float kOne = 1 << 14;
  Weights w;
  w.w00 = roundHalfEven((1.f - a) * (1.f - b) * kOne);
  w.w01 = roundHalfEven(a * (1.f - b) * kOne);
  w.w10 = roundHalfEven((1.f - a) * b * kOne);
  w.w11 = (1 << 14) - w.w00 - w.w01 - w.w10;
  return w;
}

// A level as calcOpticalFlowPyrLK reads it: the image with a reflect-101
// border, the derivatives with a zero border (buildOpticalFlowPyramid's).
HAPI_HD inline int imageAt(const Level& l, int x, int y) {
  return l.img[reflect101(y, l.height) * l.width + reflect101(x, l.width)];
}
HAPI_HD inline void derivAt(const Level& l, int x, int y, int* dx, int* dy) {
  if (x < 0 || y < 0 || x >= l.width || y >= l.height) {
    *dx = *dy = 0;
    return;
  }
  const std::int16_t* d = l.deriv + 2 * (y * l.width + x);
  *dx = d[0];
  *dy = d[1];
}

// The team that evaluates one point's window: `rank` of `size` members take
// the window's pixels rank, rank + size, ...; sum() adds the members' int64
// values (a warp on the device, a single member on the host).
struct SoloTeam {
  HAPI_HD int rank() const { return 0; }
  HAPI_HD int size() const { return 1; }
  HAPI_HD long long sum(long long v) const { return v; }
};

// One point's pyramidal LK from `prev` to `next` (levels 0..max_level each),
// calcOpticalFlowPyrLK's LKTrackerInvoker for one point over all levels.
// from: the point in the level-0 image of `prev`; *to: the initial guess
// (level 0, used when use_guess) and the result. `scratch` holds 3 window
// areas of int16 (the interpolated window of prev and its derivatives).
// Returns the status (false: lost, too flat, or left the image).
template <class Team>
HAPI_HD bool trackPoint(const Team& team, const Level* prev, const Level* next, const LkSettings& s, float fx,
                        float fy, bool use_guess, float* tx, float* ty, std::int16_t* scratch) {
  const int win = s.window, area = win * win;
  const float half = (win - 1) * 0.5f;
  std::int16_t* iwin = scratch;
  std::int16_t* dwin = scratch + area;  // dx, dy interleaved
  float nx = 0, ny = 0;                 // this level's estimate (window centre)
  bool status = true;
  for (int level = s.max_level; level >= 0; --level) {
    const float lscale = static_cast<float>(1.0 / (1 << level));
    const float px = fx * lscale, py = fy * lscale;
    if (level == s.max_level) {
      nx = use_guess ? *tx * lscale : px;
      ny = use_guess ? *ty * lscale : py;
    } else {
      nx *= 2.f;
      ny *= 2.f;
    }
    const Level& I = prev[level];
    const Level& J = next[level];
    const float ax = px - half, ay = py - half;
    const int ix = static_cast<int>(std::floor(ax)), iy = static_cast<int>(std::floor(ay));
    if (ix < -win || ix >= I.width || iy < -win || iy >= I.height) {
      if (level == 0) status = false;
      continue;
    }
    Weights w = weightsFor(ax - ix, ay - iy);
    long long a11 = 0, a12 = 0, a22 = 0;
    for (int k = team.rank(); k < area; k += team.size()) {
      const int x = ix + k % win, y = iy + k / win;
      const int v = descale(imageAt(I, x, y) * w.w00 + imageAt(I, x + 1, y) * w.w01 + imageAt(I, x, y + 1) * w.w10 +
                                imageAt(I, x + 1, y + 1) * w.w11,
                            14 - 5);
      int d[4][2];
      derivAt(I, x, y, &d[0][0], &d[0][1]);
      derivAt(I, x + 1, y, &d[1][0], &d[1][1]);
      derivAt(I, x, y + 1, &d[2][0], &d[2][1]);
      derivAt(I, x + 1, y + 1, &d[3][0], &d[3][1]);
      const int gx = descale(d[0][0] * w.w00 + d[1][0] * w.w01 + d[2][0] * w.w10 + d[3][0] * w.w11, 14);
      const int gy = descale(d[0][1] * w.w00 + d[1][1] * w.w01 + d[2][1] * w.w10 + d[3][1] * w.w11, 14);
      iwin[k] = static_cast<std::int16_t>(v);
      dwin[2 * k] = static_cast<std::int16_t>(gx);
      dwin[2 * k + 1] = static_cast<std::int16_t>(gy);
      a11 += gx * gx;
      a12 += gx * gy;
      a22 += gy * gy;
    }
    constexpr float kFltScale = 1.f / (1 << 20);
    const float A11 = static_cast<float>(team.sum(a11)) * kFltScale;
    const float A12 = static_cast<float>(team.sum(a12)) * kFltScale;
    const float A22 = static_cast<float>(team.sum(a22)) * kFltScale;
    float D = A11 * A22 - A12 * A12;
    const float min_eig = (A22 + A11 - std::sqrt((A11 - A22) * (A11 - A22) + 4.f * A12 * A12)) / (2 * area);
    if (min_eig < kMinEigThreshold || D < 1.192092896e-07f) {
      if (level == 0) status = false;
      continue;
    }
    D = 1.f / D;
    float cx = nx - half, cy = ny - half;  // window corner
    float out_x = nx, out_y = ny;
    float pdx = 0, pdy = 0;
    for (int it = 0; it < s.iterations; ++it) {
      const int jx = static_cast<int>(std::floor(cx)), jy = static_cast<int>(std::floor(cy));
      if (jx < -win || jx >= J.width || jy < -win || jy >= J.height) {
        if (level == 0) status = false;
        break;
      }
      w = weightsFor(cx - jx, cy - jy);
      long long b1 = 0, b2 = 0;
      for (int k = team.rank(); k < area; k += team.size()) {
        const int x = jx + k % win, y = jy + k / win;
        const int diff = descale(imageAt(J, x, y) * w.w00 + imageAt(J, x + 1, y) * w.w01 +
                                     imageAt(J, x, y + 1) * w.w10 + imageAt(J, x + 1, y + 1) * w.w11,
                                 14 - 5) -
                         iwin[k];
        b1 += diff * dwin[2 * k];
        b2 += diff * dwin[2 * k + 1];
      }
      const float B1 = static_cast<float>(team.sum(b1)) * kFltScale;
      const float B2 = static_cast<float>(team.sum(b2)) * kFltScale;
      const float dx = (A12 * B2 - A22 * B1) * D, dy = (A12 * B1 - A11 * B2) * D;
      cx += dx;
      cy += dy;
      out_x = cx + half;
      out_y = cy + half;
      if (static_cast<double>(dx) * dx + static_cast<double>(dy) * dy <= s.epsilon_sq) break;
      if (it > 0 && std::fabs(dx + pdx) < 0.01 && std::fabs(dy + pdy) < 0.01) {
        out_x -= dx * 0.5f;
        out_y -= dy * 0.5f;
        break;
      }
      pdx = dx;
      pdy = dy;
    }
    nx = out_x;
    ny = out_y;
  }
  *tx = nx;
  *ty = ny;
  return status;
}

// A Shi-Tomasi candidate of the search square: a local maximum of the
// thresholded minimum eigenvalue, index = y * square width + x.
struct Candidate {
  float value;
  int index;
};

// goodFeaturesToTrack's choice among the candidates: strongest first (ties:
// the later pixel first), each kept unless a kept one lies closer than
// min_distance, at most max_features. Appends (x, y) of the square to *xy.
inline void selectCorners(std::vector<Candidate>* candidates, int square_width, int max_features, double min_distance,
                          std::vector<float>* xy) {
  std::sort(candidates->begin(), candidates->end(), [](const Candidate& a, const Candidate& b) {
    return a.value > b.value || (a.value == b.value && a.index > b.index);
  });
  const double d2 = min_distance * min_distance;
  std::vector<int> kept;
  for (const Candidate& c : *candidates) {
    const int x = c.index % square_width, y = c.index / square_width;
    bool good = true;
    for (std::size_t k = 0; k < kept.size() && good; k += 2) {
      const float dx = static_cast<float>(x - kept[k]), dy = static_cast<float>(y - kept[k + 1]);
      good = !(dx * dx + dy * dy < d2);
    }
    if (!good) continue;
    kept.push_back(x);
    kept.push_back(y);
    xy->push_back(static_cast<float>(x));
    xy->push_back(static_cast<float>(y));
    if (static_cast<int>(kept.size() / 2) == max_features) break;
  }
}

}  // namespace flow_lk
}  // namespace hapi_frontend
