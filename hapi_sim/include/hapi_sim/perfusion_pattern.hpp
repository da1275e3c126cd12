// The imaging camera's known perfusion pattern (docs/DESIGN.md "Data",
// perfusion pattern): a field on the skin in perfusion units (PU), smooth
// almost everywhere with sharp steps, so that an image projected onto the
// wrong place of the surface shows at the steps. It is a function of the
// surface point's coordinates along the scene view's axes,
//   s = (X - origin) . along,  t = (X - origin) . up     [m],
// P(X) = base + wave_amplitude cos(2 pi s / wave_length) cos(2 pi t / wave_length)
//        + sum of the bands' values (a band: from <= s or t < to)
//        + sum of the discs' values ((s - s_c)^2 + (t - t_c)^2 < r^2).
// The bag carries the same numbers as YAML (/ground_truth/perfusion), which
// tools/eval/surface_metrics.py evaluates. ROS-free.
#pragma once
#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <string>
#include <vector>

#include "hapi_sim/globe_sim.hpp"
#include "hapi_sim/scene.hpp"

namespace hapi_sim {

struct PerfusionPattern {
  struct Band {
    int axis = 0;  // 0: s, 1: t
    double from = 0, to = 0, value = 0;  // m, m, PU
  };
  struct Disc {
    double s = 0, t = 0, radius = 0, value = 0;  // m, m, m, PU
  };
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d along = Eigen::Vector3d::UnitX(), up = Eigen::Vector3d::UnitY();
  double base = 300.0, wave_amplitude = 100.0, wave_length = 0.05;  // PU, PU, m
  std::vector<Band> bands;
  std::vector<Disc> discs;

  // The default pattern centred in the scene's view: two bands across s,
  // one across t and a disc, every step 150-400 PU, all within the 8 cm of a
  // scan (ViewGeometry::extent) of the centre.
  static PerfusionPattern forView(const ViewGeometry& view);
  double value(const Eigen::Vector3d& X) const;
  // /ground_truth/perfusion (the schema in tools/eval/surface_metrics.py).
  std::string yaml() const;
};

// The pattern as the camera sees it: CV_32FC1, PU, 0 where the pixel's ray
// misses the scene. One ray per pixel centre through the lens (no noise, no
// motion blur: the truth an evaluator compares against is exact).
class PerfusionRenderer {
 public:
  PerfusionRenderer(const Scene& scene, const CameraModel& cam, PerfusionPattern pattern);
  // T_sc: the camera's pose in the scene frame.
  cv::Mat render(const Pose& T_sc) const;
  const PerfusionPattern& pattern() const { return pattern_; }

 private:
  const Scene& scene_;
  CameraModel cam_;
  PerfusionPattern pattern_;
  std::vector<Eigen::Vector3d> rays_;  // h x w unit rays, camera frame
};

}  // namespace hapi_sim
