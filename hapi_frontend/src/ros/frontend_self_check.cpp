// FrontendSelfCheck (frontend_self_check.hpp).
#include "frontend_self_check.hpp"

#include "hapi_frontend/image_quality.hpp"

#include <diagnostic_msgs/DiagnosticStatus.h>

#include <cmath>
#include <cstdio>
#include <string>

namespace hapi_frontend {
namespace {

// Fewer matches leave the median of a frame to a handful of points.
constexpr size_t kMinMatchesForDisparity = 10;

std::string format(const char* fmt, double a, double b) {
  char buf[400];
  std::snprintf(buf, sizeof(buf), fmt, a, b);
  return buf;
}

}  // namespace

void FrontendSelfCheck::frameProcessed(const StereoFrameResult& r) {
  std::lock_guard<std::mutex> lock(mutex_);
  landmarks_.push_back(static_cast<double>(r.landmarks.size()));
  if (r.landmarks.size() >= kMinMatchesForDisparity && std::isfinite(r.vertical_disparity_px))
    disparity_.push_back(r.vertical_disparity_px);
  if (std::isfinite(r.motion_blur)) blur_.push_back(r.motion_blur);
}

void FrontendSelfCheck::produce(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  using diagnostic_msgs::DiagnosticStatus;
  std::vector<double> disparity, blur, landmarks;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    disparity.swap(disparity_);
    blur.swap(blur_);
    landmarks.swap(landmarks_);
  }
  const double n_frames = static_cast<double>(landmarks.size());
  const double vd = median(disparity), br = median(blur), lm = median(landmarks);
  stat.add("frames judged", n_frames);
  stat.add("vertical disparity median [px]", vd);
  stat.add("motion blur median", br);
  stat.add("landmarks per frame median", lm);

  // Worst first: every failed check is listed under its key, the summary
  // names the worst (the last one added at that level).
  std::string worst_msg = "stereo input fit for tracking";
  unsigned char worst = DiagnosticStatus::OK;
  auto check = [&](const char* key, bool failed, const std::string& msg) {
    stat.add(key, failed ? "WARN: " + msg : std::string("ok"));
    if (failed && worst == DiagnosticStatus::OK) {
      worst = DiagnosticStatus::WARN;
      worst_msg = msg;
    }
  };
  if (landmarks.empty()) {
    stat.summary(DiagnosticStatus::OK, "no frames to judge (waiting for images)");
    return;
  }
  // Rectification first: a wrong calibration also costs landmarks.
  check("check.rectification", std::fabs(vd) > t_.max_vertical_disparity_px,
        format("median vertical disparity %.2f px (> %.2f px): stereo rectification off, recalibrate the stereo "
               "pair (docs/CALIBRATION.md)",
               vd, t_.max_vertical_disparity_px));
  check("check.blur", br > t_.max_motion_blur,
        format("images smeared by motion: motion blur %.2f (> %.2f): exposure too long for the motion; shorten the "
               "exposure (more light or gain) or move slower (a striped scene also reads as smeared)",
               br, t_.max_motion_blur));
  check("check.texture", lm < t_.min_landmarks,
        format("%.0f landmarks per frame (< %.0f needed for tracking): low texture, too dark or out of focus; "
               "point the camera at a textured surface or lower fast_threshold",
               lm, static_cast<double>(t_.min_landmarks)));
  stat.summary(worst, worst_msg);
}

}  // namespace hapi_frontend
