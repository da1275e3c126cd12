// DenseDepth (dense_depth.hpp); equations: docs/DESIGN.md "Dense depth".
#include "hapi_surface/dense_depth.hpp"

#include "hapi_surface/dense_depth_block_match.hpp"
#ifdef HAPI_SURFACE_WITH_CUDA
#include "hapi_surface/cuda/dense_depth_cuda.hpp"
#endif

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace hapi_surface {

DisparitySearch disparitySearch(double min_depth, double max_depth, double f_px, double baseline) {
  const double fb = f_px * baseline;
  DisparitySearch s;
  s.min_disparity = static_cast<int>(std::floor(fb / max_depth));
  const int max_disparity = static_cast<int>(std::ceil(fb / min_depth));
  const int span = std::max(1, max_disparity - s.min_disparity + 1);
  s.num_disparities = (span + 15) / 16 * 16;
  return s;
}

DenseDepth::DenseDepth(const DenseDepthSettings& settings) : settings_(settings) {
  const std::string e = settings.validate();
  if (!e.empty()) throw std::invalid_argument("DenseDepth: " + e);
}

cv::Mat DenseDepth::disparity(const cv::Mat& left, const cv::Mat& right, const DisparitySearch& search,
                              bool* used_gpu) const {
  if (!settings_.use_gpu) return sgbmDisparity(left, right, search);
  const BlockMatchParams p{search.min_disparity, search.num_disparities, settings_.block_size,
                           settings_.uniqueness_ratio};
  const cv::Mat l = left.isContinuous() ? left : left.clone(), r = right.isContinuous() ? right : right.clone();
  cv::Mat d(left.size(), CV_32FC1);
#ifdef HAPI_SURFACE_WITH_CUDA
  if (denseDepthCudaDevice()) {
    blockMatchCuda(l.data, r.data, l.cols, l.rows, static_cast<int>(l.step), p, d.ptr<float>());
    *used_gpu = true;
    return d;
  }
#endif
  blockMatchCpu(l.data, r.data, l.cols, l.rows, static_cast<int>(l.step), p, d.ptr<float>());
  return d;
}

cv::Mat DenseDepth::sgbmDisparity(const cv::Mat& left, const cv::Mat& right, const DisparitySearch& search) const {
  const DenseDepthSettings& s = settings_;
  const int area = s.block_size * s.block_size;
  // Both modes aggregate along paths from above and from below (two passes,
  // MODE_HH4: the four axis directions). OpenCV's 5-path MODE_SGBM takes
  // only paths from the rows above in its single pass: each row leans to the
  // rows above it, 1.5 rows of the half-resolution skin scene (a step of the
  // true disparity between rows v - 1 and v came out between v and v + 1),
  // 1-3 mm across the arm (docs/DESIGN.md "Dense depth", rows; test
  // DenseDepthSim.SkinSceneDepthOnItsRow).
  cv::Ptr<cv::StereoSGBM> sgbm = cv::StereoSGBM::create(
      search.min_disparity, search.num_disparities, s.block_size, s.p1_per_pixel * area, s.p2_per_pixel * area,
      /*disp12MaxDiff=*/-1, /*preFilterCap=*/63, s.uniqueness_ratio, s.speckle_window,
      static_cast<int>(std::ceil(s.speckle_range * 16.0)), s.full_dp ? cv::StereoSGBM::MODE_HH : cv::StereoSGBM::MODE_HH4);
  // SGBM leaves the first min_disparity + num_disparities columns unmatched
  // (their search would leave the right image); the replicated border lets
  // it search them, and a true match inside the image still wins.
  const int pad = search.min_disparity + search.num_disparities;
  cv::Mat lp, rp, raw;
  cv::copyMakeBorder(left, lp, 0, 0, pad, 0, cv::BORDER_REPLICATE);
  cv::copyMakeBorder(right, rp, 0, 0, pad, 0, cv::BORDER_REPLICATE);
  sgbm->compute(lp, rp, raw);  // CV_16S, 1/16 px
  cv::Mat d;
  raw(cv::Rect(pad, 0, left.cols, left.rows)).convertTo(d, CV_32F, 1.0 / 16.0);
  return d;
}

cv::Mat DenseDepth::textureTerm(const cv::Mat& left) const {
  // Sobel's 3x3 kernel is 8 times the central difference: /8 gives grey levels per px.
  cv::Mat gx, gy;
  cv::Sobel(left, gx, CV_32F, 1, 0, 3, 1.0 / 8.0);
  cv::Sobel(left, gy, CV_32F, 0, 1, 3, 1.0 / 8.0);
  cv::Mat g2 = gx.mul(gx) + gy.mul(gy);
  cv::boxFilter(g2, g2, CV_32F, cv::Size(settings_.block_size, settings_.block_size));
  const float g0sq = static_cast<float>(settings_.texture_scale * settings_.texture_scale);
  cv::Mat denom = g2 + g0sq;
  cv::Mat t;
  cv::divide(g2, denom, t);
  return t;
}

std::string DenseDepth::compute(const cv::Mat& left, const cv::Mat& right, const RectifiedGeometry& g,
                                DepthImage* out) const {
  if (left.type() != CV_8UC1 || right.type() != CV_8UC1) return "the rectified images must be 8-bit grey";
  if (left.size() != right.size() || left.cols != g.width || left.rows != g.height)
    return "the rectified images and their geometry differ in size";
  if (!(g.fx > 0) || !(g.baseline > 0)) return "the rectified geometry needs fx > 0 and a baseline > 0";
  const DenseDepthSettings& s = settings_;
  // A disparity beyond the image width has no match; the bound also keeps
  // disparitySearch's integers finite.
  const double largest = g.fx * g.baseline / s.min_depth;
  if (!(largest <= left.cols))
    return "min_depth needs disparities up to " + std::to_string(largest) + " px, wider than the " +
           std::to_string(left.cols) + " px image (check the baseline in P, or raise min_depth)";
  const DisparitySearch search = disparitySearch(s.min_depth, s.max_depth, g.fx, g.baseline);
  bool gpu = false;
  const cv::Mat dl = disparity(left, right, search, &gpu);
  cv::Mat dr;  // right-to-left: the mirrored pair has the same disparities
  if (s.left_right_check) {
    cv::Mat lf, rf;
    cv::flip(left, lf, 1);
    cv::flip(right, rf, 1);
    cv::flip(disparity(rf, lf, search, &gpu), dr, 1);
  }
  const cv::Mat texture = textureTerm(left);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const double fb = g.fx * g.baseline;
  out->depth.create(left.size(), CV_32FC1);
  out->confidence.create(left.size(), CV_32FC1);
  out->used_gpu = gpu;
  for (int v = 0; v < left.rows; ++v) {
    const float* dlr = dl.ptr<float>(v);
    const float* tr = texture.ptr<float>(v);
    float* zr = out->depth.ptr<float>(v);
    float* cr = out->confidence.ptr<float>(v);
    for (int u = 0; u < left.cols; ++u) {
      const float d = dlr[u];
      double c = d >= search.min_disparity ? tr[u] : 0.0;
      if (c > 0 && s.left_right_check) {
        const int ur = static_cast<int>(std::lround(u - d));
        const float d2 = ur >= 0 ? dr.at<float>(v, ur) : -1.f;
        const double diff = d2 >= search.min_disparity ? std::abs(d - d2) : s.lr_tolerance + 1.0;
        c *= std::max(0.0, 1.0 - diff / s.lr_tolerance);
      }
      const double z = fb / d;
      const bool ok = c >= s.min_confidence && c > 0 && z >= s.min_depth && z <= s.max_depth;
      zr[u] = ok ? static_cast<float>(z) : nan;
      cr[u] = ok ? static_cast<float>(c) : 0.f;
    }
  }
  return "";
}

}  // namespace hapi_surface
