#include "hapi_frontend/cpu_stereo_matcher.hpp"

namespace hapi_frontend {

MatchCoreParams toMatchCoreParams(const StereoMatchParams& p) {
  MatchCoreParams c;
  c.max_epipolar_px = p.max_epipolar_px;
  c.min_disparity = p.min_disparity;
  c.max_disparity = p.max_disparity;
  c.ratio = p.ratio;
  c.max_hamming = p.max_hamming;
  c.cross_check = p.cross_check;
  return c;
}

namespace {
// Contiguous float copy of the points and a continuous descriptor block.
bool flatten(const FeatureSet& fs, const std::vector<Eigen::Vector2d>& pts, std::vector<float>* xy, cv::Mat* desc) {
  const int n = static_cast<int>(fs.keypoints.size());
  if (static_cast<int>(pts.size()) != n || fs.descriptors.rows != n || (n > 0 && fs.descriptors.type() != CV_8U))
    return false;
  xy->resize(2 * static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    (*xy)[2 * i] = static_cast<float>(pts[i].x());
    (*xy)[2 * i + 1] = static_cast<float>(pts[i].y());
  }
  *desc = fs.descriptors.isContinuous() ? fs.descriptors : fs.descriptors.clone();
  return true;
}
}  // namespace

std::vector<StereoMatch> CpuStereoMatcher::match(const FeatureSet& left, const std::vector<Eigen::Vector2d>& left_undist,
                                                 const FeatureSet& right,
                                                 const std::vector<Eigen::Vector2d>& right_undist,
                                                 const Eigen::Matrix3d& F, const StereoMatchParams& params) {
  std::vector<StereoMatch> out;
  std::vector<float> xl, xr;
  cv::Mat dl, dr;
  if (!flatten(left, left_undist, &xl, &dl) || !flatten(right, right_undist, &xr, &dr)) return out;
  if (dl.rows == 0 || dr.rows == 0 || dl.cols != dr.cols) return out;
  double f[9];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) f[3 * r + c] = F(r, c);
  const auto m = stereo_match_core(dl.data, xl.data(), dl.rows, dr.data, xr.data(), dr.rows, dl.cols, f,
                                   toMatchCoreParams(params));
  out.reserve(m.size());
  for (const auto& r : m) out.push_back({r.left, r.right, r.distance});
  return out;
}

}  // namespace hapi_frontend
