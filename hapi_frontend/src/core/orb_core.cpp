// CPU reference ORB (see orb_core.hpp for the exactness contract).
#include "hapi_frontend/orb_core.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

namespace hapi_frontend {

OrbLevelPlan orb_plan_levels(int width, int height, const OrbParams& p) {
  OrbLevelPlan plan;
  const int n = std::max(1, p.n_levels);
  double s = 1.0;
  for (int l = 0; l < n; ++l) {
    plan.width.push_back(l == 0 ? width : static_cast<int>(std::lround(width / s)));
    plan.height.push_back(l == 0 ? height : static_cast<int>(std::lround(height / s)));
    plan.scale.push_back(static_cast<float>(s));
    s *= p.scale_factor;
  }
  const double factor = 1.0 / p.scale_factor;
  double desired = n == 1 ? p.n_features : p.n_features * (1.0 - factor) / (1.0 - std::pow(factor, n));
  int sum = 0;
  for (int l = 0; l < n - 1; ++l) {
    int q = static_cast<int>(std::lround(desired));
    plan.quota.push_back(q);
    sum += q;
    desired *= factor;
  }
  plan.quota.push_back(std::max(p.n_features - sum, 0));
  return plan;
}

void orb_resize_table(int src, int dst, std::vector<int>& idx, std::vector<int>& w) {
  idx.resize(dst);
  w.resize(dst);
  for (int i = 0; i < dst; ++i) {
    long long s = ((2LL * i + 1) * src * 256) / (2LL * dst) - 128;  // Q8 source coordinate
    if (s < 0) s = 0;
    int k = static_cast<int>(s >> 8), f = static_cast<int>(s & 255);
    if (k >= src - 1) { k = src - 1; f = 0; }
    idx[i] = k;
    w[i] = f;
  }
}

namespace {

struct Tables {
  int8_t pattern[256 * 4];
  int8_t rotated[kOrbAngleBins * 256 * 4];
  int umax[kOrbHalfPatch + 1];
  Tables() {
    // Own BRIEF G II pattern: isotropic Gaussian, sigma = 31/5, clipped to
    // [-13, 13], fixed seed; generated once on the host for both paths.
    std::mt19937 rng(0x4a5b1u);
    std::uniform_real_distribution<double> uni(1e-12, 1.0);
    auto gauss = [&]() {
      double u1 = uni(rng), u2 = uni(rng);
      return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
    };
    auto coord = [&]() {
      int v = static_cast<int>(std::lround(gauss() * 31.0 / 5.0));
      return std::max(-13, std::min(13, v));
    };
    for (int i = 0; i < 256; ++i) {
      int a, b, c, d;
      do { a = coord(); b = coord(); c = coord(); d = coord(); } while (a == c && b == d);
      pattern[4 * i] = a; pattern[4 * i + 1] = b; pattern[4 * i + 2] = c; pattern[4 * i + 3] = d;
    }
    for (int bin = 0; bin < kOrbAngleBins; ++bin) {
      double th = bin * (2.0 * M_PI / kOrbAngleBins), c = std::cos(th), s = std::sin(th);
      for (int i = 0; i < 512; ++i) {
        double x = pattern[2 * i], y = pattern[2 * i + 1];
        int rx = static_cast<int>(std::lround(x * c - y * s)), ry = static_cast<int>(std::lround(x * s + y * c));
        rotated[bin * 1024 + 2 * i] = static_cast<int8_t>(std::max(-18, std::min(18, rx)));
        rotated[bin * 1024 + 2 * i + 1] = static_cast<int8_t>(std::max(-18, std::min(18, ry)));
      }
    }
    for (int v = 0; v <= kOrbHalfPatch; ++v) {
      int u = 0;
      while ((u + 1) * (u + 1) + v * v <= kOrbHalfPatch * kOrbHalfPatch + kOrbHalfPatch) ++u;
      umax[v] = u;
    }
  }
};
const Tables& tables() {
  static const Tables t;
  return t;
}

// FAST-9 circle of radius 3, clockwise from the top.
const int kCircle[16][2] = {{0, -3}, {1, -3}, {2, -2}, {3, -1}, {3, 0},  {3, 1},  {2, 2},  {1, 3},
                            {0, 3},  {-1, 3}, {-2, 2}, {-3, 1}, {-3, 0}, {-3, -1}, {-2, -2}, {-1, -3}};

}  // namespace

const int8_t* orb_pattern() { return tables().pattern; }
const int8_t* orb_rotated_patterns() { return tables().rotated; }
const int* orb_umax() { return tables().umax; }

int orb_angle_bin(long long m10, long long m01) {
  double a = std::atan2(static_cast<double>(m01), static_cast<double>(m10)) * (180.0 / M_PI);
  if (a < 0) a += 360.0;
  int bin = static_cast<int>(std::floor(a / (360.0 / kOrbAngleBins) + 0.5));
  return bin % kOrbAngleBins;
}

void orb_finalize_keypoint(OrbKeypoint& k, const OrbLevelPlan& plan) {
  const float s = plan.scale[k.level];
  k.x = static_cast<float>(k.lx) * s;
  k.y = static_cast<float>(k.ly) * s;
  k.size = 31.f * s;
  k.angle = static_cast<float>(k.angle_bin) * (360.f / kOrbAngleBins);
}

OrbResult OrbCpuCore::extract(const ImageView8& img) {
  OrbResult res;
  const OrbLevelPlan plan = orb_plan_levels(img.width, img.height, p_);
  const int nl = static_cast<int>(plan.width.size());
  levels_.resize(nl);
  smooth_.resize(nl);
  const Tables& T = tables();
  const int t = p_.fast_threshold, E = std::max(p_.edge, 19);
  std::vector<int> xi, xw, yi, yw;
  std::vector<uint64_t> keys;
  std::vector<uint32_t> tmpw;

  for (int l = 0; l < nl; ++l) {
    const int W = plan.width[l], H = plan.height[l];
    std::vector<uint8_t>& L = levels_[l];
    L.resize(static_cast<size_t>(W) * H);
    if (l == 0) {
      for (int y = 0; y < H; ++y) std::memcpy(&L[static_cast<size_t>(y) * W], img.data + static_cast<size_t>(y) * img.stride, W);
    } else {
      const int SW = plan.width[l - 1], SH = plan.height[l - 1];
      const uint8_t* S = levels_[l - 1].data();
      orb_resize_table(SW, W, xi, xw);
      orb_resize_table(SH, H, yi, yw);
      tmpw.resize(static_cast<size_t>(W) * 2);
      for (int y = 0; y < H; ++y) {
        const uint8_t* r0 = S + static_cast<size_t>(yi[y]) * SW;
        const uint8_t* r1 = S + static_cast<size_t>(std::min(yi[y] + 1, SH - 1)) * SW;
        const int fy = yw[y];
        uint8_t* d = &L[static_cast<size_t>(y) * W];
        for (int x = 0; x < W; ++x) {
          const int k = xi[x], k1 = std::min(k + 1, SW - 1), fx = xw[x];
          const int a = r0[k] * (256 - fx) + r0[k1] * fx;
          const int b = r1[k] * (256 - fx) + r1[k1] * fx;
          d[x] = static_cast<uint8_t>((a * (256 - fy) + b * fy + 32768) >> 16);
        }
      }
    }
    // 5x5 binomial smoothing, replicated border.
    std::vector<uint8_t>& Sm = smooth_[l];
    Sm.resize(L.size());
    tmp_.resize(L.size());
    for (int y = 0; y < H; ++y) {
      const uint8_t* r = &L[static_cast<size_t>(y) * W];
      uint16_t* o = &tmp_[static_cast<size_t>(y) * W];
      for (int x = 0; x < W; ++x) {
        const int xm2 = std::max(x - 2, 0), xm1 = std::max(x - 1, 0), xp1 = std::min(x + 1, W - 1), xp2 = std::min(x + 2, W - 1);
        o[x] = static_cast<uint16_t>(r[xm2] + 4 * r[xm1] + 6 * r[x] + 4 * r[xp1] + r[xp2]);
      }
    }
    for (int y = 0; y < H; ++y) {
      const uint16_t* a = &tmp_[static_cast<size_t>(std::max(y - 2, 0)) * W];
      const uint16_t* b = &tmp_[static_cast<size_t>(std::max(y - 1, 0)) * W];
      const uint16_t* c = &tmp_[static_cast<size_t>(y) * W];
      const uint16_t* d = &tmp_[static_cast<size_t>(std::min(y + 1, H - 1)) * W];
      const uint16_t* e = &tmp_[static_cast<size_t>(std::min(y + 2, H - 1)) * W];
      uint8_t* o = &Sm[static_cast<size_t>(y) * W];
      for (int x = 0; x < W; ++x) o[x] = static_cast<uint8_t>((a[x] + 4 * b[x] + 6 * c[x] + 4 * d[x] + e[x] + 128) >> 8);
    }
    // FAST-9 score on [E-1, W-E] x [E-1, H-E], zero elsewhere.
    score_.assign(L.size(), 0);
    if (W <= 2 * E + 2 || H <= 2 * E + 2) continue;
    int off[16];
    for (int i = 0; i < 16; ++i) off[i] = kCircle[i][1] * W + kCircle[i][0];
    for (int y = E - 1; y <= H - E; ++y) {
      const uint8_t* row = &L[static_cast<size_t>(y) * W];
      uint8_t* srow = &score_[static_cast<size_t>(y) * W];
      for (int x = E - 1; x <= W - E; ++x) {
        const uint8_t* p = row + x;
        const int c = p[0];
        int nb = 0, nd = 0;
        for (int i = 0; i < 16; i += 4) {
          const int v = p[off[i]];
          nb += v > c + t;
          nd += v < c - t;
        }
        if (nb < 2 && nd < 2) continue;
        int d[16];
        for (int i = 0; i < 16; ++i) d[i] = p[off[i]] - c;
        int best = 0;
        for (int k = 0; k < 16; ++k) {
          int mn = 255, mx = -255;
          for (int j = 0; j < 9; ++j) {
            const int v = d[(k + j) & 15];
            mn = std::min(mn, v);
            mx = std::max(mx, v);
          }
          best = std::max(best, std::max(mn, -mx));
        }
        if (best > t) srow[x] = static_cast<uint8_t>(best);
      }
    }
    // 3x3 strict non-maximum suppression, ranking, retention.
    keys.clear();
    for (int y = E; y < H - E; ++y) {
      const uint8_t* s = &score_[static_cast<size_t>(y) * W];
      for (int x = E; x < W - E; ++x) {
        const int v = s[x];
        if (!v) continue;
        if (v > s[x - 1] && v > s[x + 1] && v > s[x - W - 1] && v > s[x - W] && v > s[x - W + 1] && v > s[x + W - 1] &&
            v > s[x + W] && v > s[x + W + 1])
          keys.push_back(orb_rank_key(v, y, x));
      }
    }
    const size_t q = std::min<size_t>(plan.quota[l], keys.size());
    std::partial_sort(keys.begin(), keys.begin() + q, keys.end());
    // Orientation (intensity centroid on the level image) and steered BRIEF.
    for (size_t i = 0; i < q; ++i) {
      OrbKeypoint k;
      k.level = l;
      k.score = 255 - static_cast<int>(keys[i] >> 40);
      k.ly = static_cast<int>((keys[i] >> 20) & 0xFFFFF);
      k.lx = static_cast<int>(keys[i] & 0xFFFFF);
      const uint8_t* c = &L[static_cast<size_t>(k.ly) * W + k.lx];
      long long m10 = 0, m01 = 0;
      for (int v = -kOrbHalfPatch; v <= kOrbHalfPatch; ++v) {
        const int um = T.umax[v < 0 ? -v : v];
        const uint8_t* r = c + v * W;
        int rs = 0, rx = 0;
        for (int u = -um; u <= um; ++u) {
          rs += r[u];
          rx += u * r[u];
        }
        m10 += rx;
        m01 += static_cast<long long>(v) * rs;
      }
      k.angle_bin = orb_angle_bin(m10, m01);
      orb_finalize_keypoint(k, plan);
      const int8_t* pat = &T.rotated[k.angle_bin * 1024];
      const uint8_t* sc = &Sm[static_cast<size_t>(k.ly) * W + k.lx];
      uint8_t desc[kOrbDescBytes];
      for (int b = 0; b < kOrbDescBytes; ++b) {
        int val = 0;
        for (int j = 0; j < 8; ++j) {
          const int8_t* pp = pat + (b * 8 + j) * 4;
          val |= (sc[pp[1] * W + pp[0]] < sc[pp[3] * W + pp[2]]) << j;
        }
        desc[b] = static_cast<uint8_t>(val);
      }
      res.keypoints.push_back(k);
      res.descriptors.insert(res.descriptors.end(), desc, desc + kOrbDescBytes);
    }
  }
  return res;
}

}  // namespace hapi_frontend
