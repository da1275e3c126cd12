#include "hapi_frontend/stereo_refine.hpp"

#include <cmath>
#include <cstdint>

namespace hapi_frontend {

namespace {
// Vertex of the parabola through (-1, a), (0, b), (1, c); in [-0.5, 0.5]
// when b is the discrete maximum.
double parabolaPeak(double a, double b, double c) {
  const double den = a - 2.0 * b + c;
  if (!(den < 0)) return 0.0;
  const double d = 0.5 * (a - c) / den;
  return std::max(-0.5, std::min(0.5, d));
}
}  // namespace

RefineResult refineStereoMatch(const cv::Mat& left, const cv::Mat& right, const cv::Point2f& pl,
                               const cv::Point2f& pr, const RefineParams& p) {
  RefineResult r;
  const int h = p.half_patch, R = p.radius, n = 2 * h + 1;
  if (h < 1 || h > 30 || R < 1 || R > 30 || left.type() != CV_8UC1 || right.type() != CV_8UC1) return r;
  // Whole left patch and right search window inside the images (no border
  // replication: a replicated border would correlate with anything).
  const int cx = static_cast<int>(std::lround(pr.x)), cy = static_cast<int>(std::lround(pr.y));
  if (pl.x - h - 1 < 0 || pl.y - h - 1 < 0 || pl.x + h + 1 >= left.cols || pl.y + h + 1 >= left.rows) return r;
  if (cx - h - R < 0 || cy - h - R < 0 || cx + h + R >= right.cols || cy + h + R >= right.rows) return r;
  // Left patch, bilinear (keypoints of pyramid levels > 0 sit between
  // pixels), zero-mean; the ZNCC is then cross / (|patch| * std(window)).
  const int np = n * n;
  float patch[61 * 61];
  {
    const int x0 = static_cast<int>(std::floor(pl.x)) - h, y0 = static_cast<int>(std::floor(pl.y)) - h;
    const float ax = pl.x - std::floor(pl.x), ay = pl.y - std::floor(pl.y);
    const float w00 = (1 - ax) * (1 - ay), w01 = ax * (1 - ay), w10 = (1 - ax) * ay, w11 = ax * ay;
    double sum = 0;
    for (int v = 0; v < n; ++v) {
      const uint8_t* r0 = left.ptr<uint8_t>(y0 + v) + x0;
      const uint8_t* r1 = left.ptr<uint8_t>(y0 + v + 1) + x0;
      for (int u = 0; u < n; ++u) {
        const float val = w00 * r0[u] + w01 * r0[u + 1] + w10 * r1[u] + w11 * r1[u + 1];
        patch[v * n + u] = val;
        sum += val;
      }
    }
    const float mean = static_cast<float>(sum / np);
    for (int k = 0; k < np; ++k) patch[k] -= mean;
  }
  double pnorm2 = 0;
  for (int k = 0; k < np; ++k) pnorm2 += static_cast<double>(patch[k]) * patch[k];
  if (!(pnorm2 > 1e-6 * np)) return r;  // flat patch: no texture to align
  const int S = 2 * R + 1;
  float score[61 * 61];
  for (int dy = 0; dy < S; ++dy)
    for (int dx = 0; dx < S; ++dx) {
      int sr = 0, sr2 = 0;
      float cross = 0.f;
      for (int v = 0; v < n; ++v) {
        const uint8_t* row = right.ptr<uint8_t>(cy - h - R + dy + v) + (cx - h - R + dx);
        const float* pr_row = patch + v * n;
        for (int u = 0; u < n; ++u) {
          const int val = row[u];
          sr += val;
          sr2 += val * val;
          cross += pr_row[u] * static_cast<float>(val);
        }
      }
      const double var = static_cast<double>(sr2) - static_cast<double>(sr) * sr / np;
      score[dy * S + dx] = var > 1e-6 ? static_cast<float>(cross / std::sqrt(pnorm2 * var)) : -1.f;
    }
  double best = -2;
  cv::Point bp(0, 0);
  for (int dy = 0; dy < S; ++dy)
    for (int dx = 0; dx < S; ++dx)
      if (score[dy * S + dx] > best) {
        best = score[dy * S + dx];
        bp = cv::Point(dx, dy);
      }
  r.zncc = best;
  // A peak on the border of the search window is not a peak (the true match
  // may lie outside).
  if (!(best >= p.min_zncc) || bp.x == 0 || bp.y == 0 || bp.x == 2 * R || bp.y == 2 * R) return r;
  auto at = [&](int x, int y) { return static_cast<double>(score[y * S + x]); };
  const double dx = parabolaPeak(at(bp.x - 1, bp.y), at(bp.x, bp.y), at(bp.x + 1, bp.y));
  const double dy = parabolaPeak(at(bp.x, bp.y - 1), at(bp.x, bp.y), at(bp.x, bp.y + 1));
  r.right = cv::Point2f(static_cast<float>(cx + (bp.x - R) + dx), static_cast<float>(cy + (bp.y - R) + dy));
  r.ok = true;
  return r;
}

}  // namespace hapi_frontend
