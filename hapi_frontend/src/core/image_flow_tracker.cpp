// ImageFlowTracker (image_flow_tracker.hpp): restarts, the processed window,
// corners, forward-backward LK and the affine fit.
#include "hapi_frontend/image_flow_tracker.hpp"

#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace hapi_frontend {
namespace {

std::string sizeText(const cv::Size& s) { return std::to_string(s.width) + "x" + std::to_string(s.height); }

}  // namespace

ImageFlowTracker::ImageFlowTracker(const ImageFlowParams& params) : params_(params) {
  const std::string invalid = params_.validate();
  if (!invalid.empty()) throw std::invalid_argument("image flow settings: " + invalid);
  fit_.huber_k = params_.huber_k;
  fit_.outlier_sigmas = params_.outlier_sigmas;
  fit_.min_sigma = params_.min_sigma;
  fit_.min_inliers = params_.min_inliers;
  win_ = cv::Size(params_.lk_window, params_.lk_window);
}

bool ImageFlowTracker::layoutFor(const cv::Size& size) {
  size_ = size;
  have_layout_ = false;
  const double u = params_.u < 0 ? 0.5 * (size.width - 1) : params_.u;
  const double v = params_.v < 0 ? 0.5 * (size.height - 1) : params_.v;
  if (u > size.width - 1 || v > size.height - 1) return false;
  pixel_ = Eigen::Vector2d(u, v);
  // The window: the search square plus room for a corner's LK window at the
  // coarsest level and for its motion (up to a window side at that level),
  // so border replication rarely enters a window.
  const int r = params_.search_radius;
  const int margin = params_.lk_window * (1 << (params_.pyramid_levels - 1));
  const int cu = static_cast<int>(std::lround(u)), cv_ = static_cast<int>(std::lround(v));
  const cv::Rect image(0, 0, size.width, size.height);
  roi_ = cv::Rect(cu - r - margin, cv_ - r - margin, 2 * (r + margin) + 1, 2 * (r + margin) + 1) & image;
  search_ = (cv::Rect(cu - r, cv_ - r, 2 * r + 1, 2 * r + 1) & image) - roi_.tl();
  have_layout_ = true;
  return true;
}

void ImageFlowTracker::keepAsPrevious(const cv::Mat& window, std::vector<cv::Mat>&& pyramid, std::int64_t stamp_ns) {
  previous_pyramid_ = std::move(pyramid);
  previous_corners_.clear();
  // goodFeaturesToTrack needs a block (3 px) inside the square.
  if (search_.width >= 3 && search_.height >= 3) {
    cv::goodFeaturesToTrack(window(search_), previous_corners_, params_.max_features, params_.feature_quality,
                            params_.min_feature_distance);
    for (cv::Point2f& p : previous_corners_) p += cv::Point2f(search_.tl());
  }
  previous_stamp_ns_ = stamp_ns;
  have_previous_ = true;
}

void ImageFlowTracker::track(const std::vector<cv::Mat>& pyramid, ImageFlowResult* out) const {
  out->tracked = static_cast<std::uint32_t>(previous_corners_.size());
  out->status = FlowStatus::kTooFewFeatures;
  if (static_cast<int>(previous_corners_.size()) < params_.min_inliers) return;
  const cv::TermCriteria stop(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, params_.lk_iterations,
                              params_.lk_epsilon);
  const int max_level = params_.pyramid_levels - 1;
  std::vector<cv::Point2f> ahead, back;
  std::vector<std::uint8_t> ok_ahead, ok_back;
  std::vector<float> err;
  cv::calcOpticalFlowPyrLK(previous_pyramid_, pyramid, previous_corners_, ahead, ok_ahead, err, win_, max_level,
                           stop);
  // Backwards from where each corner landed, started at its origin.
  back = previous_corners_;
  cv::calcOpticalFlowPyrLK(pyramid, previous_pyramid_, ahead, back, ok_back, err, win_, max_level, stop,
                           cv::OPTFLOW_USE_INITIAL_FLOW);
  const cv::Rect2f inside(0.f, 0.f, static_cast<float>(roi_.width - 1), static_cast<float>(roi_.height - 1));
  std::vector<Eigen::Vector2d> from, moved;
  const Eigen::Vector2d offset(roi_.x, roi_.y);
  for (std::size_t i = 0; i < previous_corners_.size(); ++i) {
    if (!ok_ahead[i] || !ok_back[i] || !inside.contains(ahead[i])) continue;
    const cv::Point2f fb = back[i] - previous_corners_[i];
    if (!(std::hypot(fb.x, fb.y) <= params_.fb_threshold)) continue;
    from.emplace_back(Eigen::Vector2d(previous_corners_[i].x, previous_corners_[i].y) + offset);
    moved.emplace_back(ahead[i].x - previous_corners_[i].x, ahead[i].y - previous_corners_[i].y);
  }
  out->consistent = static_cast<std::uint32_t>(from.size());
  const AffineFlowFit fit = fitAffineFlow(from, moved, pixel_, fit_);
  out->inliers = static_cast<std::uint32_t>(fit.inliers);
  if (!fit.ok) return;
  out->status = FlowStatus::kOk;
  out->affine = fit.affine;
  out->covariance = fit.covariance * overlapInflation(from, fit.inlier);
  out->sigma = fit.sigma;
}

double ImageFlowTracker::overlapInflation(const std::vector<Eigen::Vector2d>& from,
                                          const std::vector<bool>& inlier) const {
  // LK windows of nearby corners share pixels, so their errors are
  // correlated and the fit's independent-residual covariance is too small
  // (docs/DESIGN.md "Surface motion: image flow"): m inliers whose windows
  // cover an area A carry about n_eff = A / window area independent
  // measurements, and the covariance is scaled by m / n_eff (>= 1).
  cv::Mat covered(roi_.size(), CV_8UC1, cv::Scalar(0));
  const int half = params_.lk_window / 2;
  int m = 0;
  for (std::size_t i = 0; i < from.size(); ++i) {
    if (!inlier[i]) continue;
    ++m;
    const cv::Point c(static_cast<int>(std::lround(from[i].x())) - roi_.x,
                      static_cast<int>(std::lround(from[i].y())) - roi_.y);
    cv::rectangle(covered, cv::Rect(c.x - half, c.y - half, params_.lk_window, params_.lk_window), cv::Scalar(1),
                  cv::FILLED);
  }
  const double n_eff = std::max(1.0, cv::countNonZero(covered) / double(params_.lk_window * params_.lk_window));
  return std::max(1.0, m / n_eff);
}

InputError ImageFlowTracker::process(const cv::Mat& grey, std::int64_t stamp_ns, ImageFlowResult* out) {
  *out = ImageFlowResult{};
  out->stamp_ns = stamp_ns;
  out->previous_stamp_ns = have_previous_ ? previous_stamp_ns_ : 0;
  out->restart_reason = "start";
  if (grey.empty() || grey.type() != CV_8UC1)
    return InputError{"malformed_image", "the tracker needs a non-empty 8-bit grey image"};
  InputError error;
  if (!have_layout_ || grey.size() != size_) {
    if (have_layout_)
      error = InputError{"size_changed", "image size changed from " + sizeText(size_) + " to " + sizeText(grey.size())};
    have_previous_ = false;
    if (!layoutFor(grey.size())) {
      std::ostringstream os;
      os << "pixel (" << params_.u << ", " << params_.v << ") is outside the " << sizeText(grey.size()) << " image";
      return InputError{"pixel_outside_image", os.str()};
    }
  }
  out->u = pixel_.x();
  out->v = pixel_.y();
  const std::int64_t max_gap_ns = static_cast<std::int64_t>(params_.max_gap * 1e9);
  if (have_previous_ && stamp_ns <= previous_stamp_ns_) out->restart_reason = "stamp_not_increasing";
  else if (have_previous_ && stamp_ns - previous_stamp_ns_ > max_gap_ns) out->restart_reason = "gap";
  else if (error) out->restart_reason = "size_changed";
  else if (have_previous_) out->restart_reason.clear();

  const cv::Mat window = grey(roi_);
  std::vector<cv::Mat> pyramid;
  // Never reuse the input as level 0 (tryReuseInputImage = false): the
  // pyramid outlives this call, the caller's buffer (a message) need not.
  cv::buildOpticalFlowPyramid(window, pyramid, win_, params_.pyramid_levels - 1, true, cv::BORDER_REFLECT_101,
                              cv::BORDER_CONSTANT, false);
  if (out->restart_reason.empty()) track(pyramid, out);
  keepAsPrevious(window, std::move(pyramid), stamp_ns);
  return error;
}

}  // namespace hapi_frontend
