// The front end's self-checks of its input, published as their own
// diagnostic_updater task ("self-check"): is the stereo pair rectified (the
// median vertical disparity of the matches), are the images sharp (motion
// blur) and textured enough for tracking (landmarks per frame). Each check
// judges the frames since the previous report and names the number and the
// likely cause (docs/CALIBRATION.md "Self-checks"). Thresholds:
// FrontendNodeletParams (check_*).
#pragma once

#include "hapi_frontend/stereo_pipeline.hpp"

#include <diagnostic_updater/DiagnosticStatusWrapper.h>

#include <mutex>
#include <vector>

namespace hapi_frontend {

struct SelfCheckThresholds {
  double max_vertical_disparity_px = 0.5;
  double max_motion_blur = 0.4;
  int min_landmarks = 30;
};

class FrontendSelfCheck {
 public:
  explicit FrontendSelfCheck(const SelfCheckThresholds& t) : t_(t) {}
  void frameProcessed(const StereoFrameResult& result);
  // diagnostic_updater task: judges the frames since the previous call.
  void produce(diagnostic_updater::DiagnosticStatusWrapper& stat);

 private:
  const SelfCheckThresholds t_;
  std::mutex mutex_;
  std::vector<double> disparity_, blur_, landmarks_;
};

}  // namespace hapi_frontend
