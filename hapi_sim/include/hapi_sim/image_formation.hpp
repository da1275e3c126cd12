// hapi_sim: image formation of the simulation suite: a ray-casting renderer
// of any Scene with motion blur (sub-frame renders along the true trajectory
// over the exposure), the camera's gain over time (slow drift + steps, as an
// auto-exposure does) and the sensor (shot + read noise, 8-bit quantisation).
// All seeded. Parameters: docs/DESIGN.md "Data".
#pragma once
#include <opencv2/core.hpp>
#include <cstdint>
#include <vector>

#include "hapi_sim/globe_sim.hpp"
#include "hapi_sim/scene.hpp"

namespace hapi_sim {

// Renders the radiance (grey level at unit gain, CV_32FC1) of a Scene.
// Sub-frame j uses pose j and one of four sub-pixel offsets (j mod 4, a 2x2
// pattern), so four or more sub-frames also anti-alias like 2x2
// supersampling. Rows run in parallel; the result does not depend on it.
class SceneRenderer {
 public:
  SceneRenderer(const Scene& scene, const CameraModel& cam);
  // T_sc: camera -> scene poses of the sub-frames (at least one).
  cv::Mat radiance(const std::vector<Pose>& T_sc) const;
  static constexpr int kOffsets = 4;

 private:
  const Scene& scene_;
  CameraModel cam_;
  std::vector<Eigen::Vector3f> rays_[kOffsets];  // per offset: h x w unit rays, camera frame
};

// Global gain over time: 1 + 10 % slow drift (period 11-17 s) times a level
// that steps every 3-6 s to a new value in [0.8, 1.2]. Off: gain 1.
class ExposureModel {
 public:
  ExposureModel(uint32_t seed, bool enabled);
  double gain(double t) const;

 private:
  bool enabled_;
  double drift_period_ = 13.0, drift_phase_ = 0.0;
  std::vector<double> step_times_, step_levels_;
};

// Shot noise (Gaussian approximation of Poisson, 16 electrons per grey
// level: 255 grey = 4080 e-, a small-pixel sensor's full well) plus read
// noise (1.2 grey), then rounding and clipping to 8 bits.
struct SensorNoise {
  double electrons_per_grey = 16.0;
  double read_noise = 1.2;  // grey levels
  bool enabled = true;
  // radiance * gain + noise -> mono8; seed drives the noise only.
  cv::Mat expose(const cv::Mat& radiance, double gain, uint32_t seed) const;
};

}  // namespace hapi_sim
