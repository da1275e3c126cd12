// Procedural textures of the skin scene: skin (low contrast: mottling,
// pores, skin lines, veins, freckles; no markers) and table wood. Integer
// hashing only, so the fields are identical on every platform; they depend
// on no dataset seed (the scene is the same for every seed).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "hapi_sim/globe_sim.hpp"
#include "hapi_sim/scene.hpp"

namespace hapi_sim {
namespace {

uint32_t hash3(int32_t x, int32_t y, uint32_t seed) {
  uint32_t h = seed * 0x9E3779B1u ^ static_cast<uint32_t>(x) * 0x85EBCA77u ^ static_cast<uint32_t>(y) * 0xC2B2AE3Du;
  h ^= h >> 15; h *= 0x2C1B3C6Du; h ^= h >> 12; h *= 0x297A2D39u; h ^= h >> 15;
  return h;
}

double lattice(int32_t x, int32_t y, uint32_t seed) { return hash3(x, y, seed) * (2.0 / 4294967295.0) - 1.0; }

// Value noise in [-1, 1] with quintic interpolation (C2 across cells).
double valueNoise(double x, double y, uint32_t seed) {
  const double fx = std::floor(x), fy = std::floor(y);
  const int32_t ix = static_cast<int32_t>(fx), iy = static_cast<int32_t>(fy);
  auto fade = [](double t) { return t * t * t * (t * (t * 6 - 15) + 10); };
  const double u = fade(x - fx), v = fade(y - fy);
  const double a = lattice(ix, iy, seed), b = lattice(ix + 1, iy, seed);
  const double c = lattice(ix, iy + 1, seed), d = lattice(ix + 1, iy + 1, seed);
  return (a + (b - a) * u) * (1 - v) + (c + (d - c) * u) * v;
}

// Fractal sum of octaves (each half the size and half the amplitude).
double fbm(double x, double y, int octaves, uint32_t seed) {
  double sum = 0, amp = 0.5, norm = 0;
  for (int o = 0; o < octaves; ++o) {
    sum += amp * valueNoise(x, y, seed + 101u * o);
    norm += amp;
    x *= 2.0; y *= 2.0; amp *= 0.5;
  }
  return sum / norm;
}

// Adds depth * profile(r / radius) in a disc (profile 1 at the centre, 0 at
// the rim, smooth): freckles and pores. Coordinates in texels; u wraps.
void stamp(cv::Mat* tex, double cu, double cv_, double radius, double depth) {
  const int W = tex->cols, H = tex->rows, R = static_cast<int>(std::ceil(radius)) + 1;
  for (int dv = -R; dv <= R; ++dv) {
    const int v = static_cast<int>(std::lround(cv_)) + dv;
    if (v < 0 || v >= H) continue;
    for (int du = -R; du <= R; ++du) {
      const int u = static_cast<int>(std::lround(cu)) + du;
      const double r = std::hypot(u - cu, v - cv_) / radius;
      if (r >= 1.0) continue;
      const double s = 1.0 - r * r;
      tex->at<float>(v, ((u % W) + W) % W) += static_cast<float>(depth * s * s);
    }
  }
}

}  // namespace

cv::Mat makeSkinTexture(int width, int height, double texel, uint32_t seed) {
  const uint32_t o = 1000u * seed;  // 0: the reference skin
  cv::Mat tex(height, width, CV_32FC1);
  const double mm = 1e-3;
  for (int v = 0; v < height; ++v) {
    float* row = tex.ptr<float>(v);
    const double y = v * texel;  // along the arm
    for (int u = 0; u < width; ++u) {
      const double x = u * texel;  // around the arm
      double g = 148.0;
      g += 7.0 * fbm(x / (14 * mm), y / (14 * mm), 4, o + 11u);   // mottling
      g += 2.5 * fbm(x / (1.2 * mm), y / (1.2 * mm), 2, o + 23u);  // fine grain
      // Skin lines: two crossing families of shallow furrows, 1.3 mm apart,
      // their depth modulated so the pattern is irregular.
      const double l1 = std::cos(2 * M_PI * (0.87 * x + 0.50 * y) / (1.3 * mm) + 3.0 * valueNoise(x / (4 * mm), y / (4 * mm), o + 31u));
      const double l2 = std::cos(2 * M_PI * (-0.50 * x + 0.87 * y) / (1.3 * mm) + 3.0 * valueNoise(x / (4 * mm), y / (4 * mm), o + 37u));
      const double depth = 2.0 + 1.5 * valueNoise(x / (6 * mm), y / (6 * mm), o + 41u);
      g -= depth * (std::pow(std::max(0.0, l1), 6) + std::pow(std::max(0.0, l2), 6));
      row[u] = static_cast<float>(g);
    }
  }
  // Veins: three darker smooth bands, 2-3 mm wide, meandering along the arm.
  for (int k = 0; k < 3; ++k) {
    const double u0 = width * (0.12 + 0.3 * k), amp = (4 + 2 * k) * mm / texel, len = (35 + 10 * k) * mm / texel;
    const double w = (2.0 + 0.5 * k) * mm / texel;
    for (int v = 0; v < height; ++v) {
      const double uc = u0 + amp * std::sin(v / len + k);
      for (int du = -static_cast<int>(3 * w); du <= static_cast<int>(3 * w); ++du) {
        const int u = static_cast<int>(std::lround(uc)) + du;
        const double r = (u - uc) / w;
        tex.at<float>(v, ((u % width) + width) % width) -= static_cast<float>(7.0 * std::exp(-r * r));
      }
    }
  }
  // Pores (about 15 per cm^2, 0.10-0.22 mm) and freckles (about 0.8 per cm^2,
  // 0.5-1.6 mm, 18-42 grey levels darker): the corners a detector can hold on to.
  GaussianRng rng(0x5C1Du + seed);
  const double area_cm2 = width * height * texel * texel * 1e4;
  for (int i = 0, n = static_cast<int>(15 * area_cm2); i < n; ++i) {
    const double cu = rng.uniform01() * width, cvv = rng.uniform01() * height;
    stamp(&tex, cu, cvv, (0.10 + 0.12 * rng.uniform01()) * mm / texel, -(6.0 + 8.0 * rng.uniform01()));
  }
  for (int i = 0, n = static_cast<int>(2.0 * area_cm2); i < n; ++i) {
    const double cu = rng.uniform01() * width, cvv = rng.uniform01() * height;
    stamp(&tex, cu, cvv, (0.6 + 1.2 * rng.uniform01()) * mm / texel, -(18.0 + 24.0 * rng.uniform01()));
  }
  return tex;
}

cv::Mat makeWoodTexture(int width, int height, double texel) {
  cv::Mat tex(height, width, CV_32FC1);
  for (int v = 0; v < height; ++v) {
    float* row = tex.ptr<float>(v);
    const double y = v * texel;
    for (int u = 0; u < width; ++u) {
      const double x = u * texel;  // grain runs along x
      // Rings 8 mm apart, distorted by a slow and a faster warp (which also
      // bends them into the eyes of cut growth rings).
      const double warp = 2.5 * fbm(x / 0.25, y / 0.06, 3, 53u) + 0.6 * fbm(x / 0.03, y / 0.01, 2, 67u);
      double g = 105.0 + 16.0 * std::sin(2 * M_PI * (y / 0.008 + warp));
      g += 7.0 * fbm(x / 0.04, y / 0.0015, 3, 59u);  // fine grain, stretched along x
      g += 6.0 * fbm(x / 0.15, y / 0.15, 2, 61u);    // slow colour variation
      row[u] = static_cast<float>(g);
    }
  }
  return tex;
}

}  // namespace hapi_sim
