#include "hapi_frontend/stereo_refine.hpp"

#include <opencv2/imgproc.hpp>

#include <cmath>

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
  const int h = p.half_patch, R = p.radius, n = 2 * h + 1, m = n + 2 * R;
  // Whole left patch and right search window inside the images (no border
  // replication: a replicated border would correlate with anything).
  const int cx = static_cast<int>(std::lround(pr.x)), cy = static_cast<int>(std::lround(pr.y));
  if (pl.x - h - 1 < 0 || pl.y - h - 1 < 0 || pl.x + h + 1 >= left.cols || pl.y + h + 1 >= left.rows) return r;
  if (cx - h - R < 0 || cy - h - R < 0 || cx + h + R >= right.cols || cy + h + R >= right.rows) return r;
  cv::Mat patch, window, score;
  // Left keypoints of pyramid levels > 0 sit between pixels: bilinear patch.
  cv::getRectSubPix(left, cv::Size(n, n), pl, patch, CV_32F);
  right(cv::Rect(cx - h - R, cy - h - R, m, m)).convertTo(window, CV_32F);
  cv::matchTemplate(window, patch, score, cv::TM_CCOEFF_NORMED);
  double best;
  cv::Point bp;
  cv::minMaxLoc(score, nullptr, &best, nullptr, &bp);
  r.zncc = best;
  // A peak on the border of the search window is not a peak (the true match
  // may lie outside); a flat patch gives NaN and fails the comparison.
  if (!(best >= p.min_zncc) || bp.x == 0 || bp.y == 0 || bp.x == 2 * R || bp.y == 2 * R) return r;
  const float* row = score.ptr<float>(bp.y);
  const double dx = parabolaPeak(row[bp.x - 1], row[bp.x], row[bp.x + 1]);
  const double dy = parabolaPeak(score.at<float>(bp.y - 1, bp.x), row[bp.x], score.at<float>(bp.y + 1, bp.x));
  r.right = cv::Point2f(static_cast<float>(cx + (bp.x - R) + dx), static_cast<float>(cy + (bp.y - R) + dy));
  r.ok = true;
  return r;
}

}  // namespace hapi_frontend
