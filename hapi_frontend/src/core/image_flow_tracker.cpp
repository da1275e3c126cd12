// ImageFlowTracker (image_flow_tracker.hpp): the backend, restarts, the
// processed window, the checks of the tracks and the affine fit.
#include "hapi_frontend/image_flow_tracker.hpp"

#include <opencv2/imgproc.hpp>

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
  if (params_.use_gpu) {
    std::string why;
    stage_ = makeCudaFlowStage(params_, &why);
    backend_status_ = stage_ ? why : why + ", using the CPU";
  } else {
    backend_status_ = "CPU (use_gpu not set)";
  }
  if (!stage_) stage_ = makeCpuFlowStage(params_);
}

ImageFlowTracker::~ImageFlowTracker() = default;

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

void ImageFlowTracker::fit(const FlowTracks& tracks, ImageFlowResult* out) const {
  out->tracked = static_cast<std::uint32_t>(tracks.from.size());
  out->status = FlowStatus::kTooFewFeatures;
  if (static_cast<int>(tracks.from.size()) < params_.min_inliers) return;
  const cv::Rect2f inside(0.f, 0.f, static_cast<float>(roi_.width - 1), static_cast<float>(roi_.height - 1));
  std::vector<Eigen::Vector2d> from, moved;
  const Eigen::Vector2d offset(roi_.x, roi_.y);
  for (std::size_t i = 0; i < tracks.from.size(); ++i) {
    if (!tracks.ok[i] || !inside.contains(tracks.ahead[i])) continue;
    const cv::Point2f fb = tracks.back[i] - tracks.from[i];
    if (!(std::hypot(fb.x, fb.y) <= params_.fb_threshold)) continue;
    from.emplace_back(Eigen::Vector2d(tracks.from[i].x, tracks.from[i].y) + offset);
    moved.emplace_back(tracks.ahead[i].x - tracks.from[i].x, tracks.ahead[i].y - tracks.from[i].y);
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

  const bool track = out->restart_reason.empty();
  FlowTracks tracks;
  try {
    stage_->frame(grey(roi_), search_, track, &tracks);
  } catch (const std::runtime_error& e) {
    if (!stage_->onGpu()) throw;
    // The device state is lost: the CPU takes over from this frame.
    backend_status_ = std::string("CUDA failed at run time (") + e.what() + "), switched to the CPU";
    stage_ = makeCpuFlowStage(params_);
    out->restart_reason = "gpu_failed";
    stage_->frame(grey(roi_), search_, false, &tracks);
  }
  if (out->restart_reason.empty()) fit(tracks, out);
  previous_stamp_ns_ = stamp_ns;
  have_previous_ = true;
  return error;
}

}  // namespace hapi_frontend
