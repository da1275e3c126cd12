// One image-flow measurement of the imaging camera (hapi_msgs/ImageFlow in
// plain C++), its input checks, and its model (docs/DESIGN.md "Surface
// motion", fusion): the pixel's displacement over [t_prev, t] predicted from
// the camera's pose change over that interval and the extra skin velocity e.
#pragma once

#include "hapi_eskf/surface_motion/imaging_camera.hpp"
#include "hapi_eskf/surface_motion/velocity_map.hpp"

#include <array>
#include <string>

namespace hapi_eskf {
namespace surface_motion {

struct FlowMeasurement {
  enum Status : uint8_t { kOk = 0, kTooFewFeatures = 1, kFirstFrame = 2 };
  double t_prev = 0, t = 0;  // [s]
  double u = 0, v = 0;       // [px] the pixel the flow is about
  // affine[0:2]: the pixel's displacement over [t_prev, t] [px]; affine[2:6]
  // its gradient (ImageFlow.msg).
  std::array<double, 6> affine{{0, 0, 0, 0, 0, 0}};
  std::array<double, 36> covariance{};  // row-major 6x6
  uint32_t inliers = 0, tracked = 0;
  uint8_t status = kOk;

  Vec2 displacement() const { return Vec2(affine[0], affine[1]); }
  Mat2 displacementCovariance() const;
};

// "" when the measurement may be fused, else why not: a status not OK, a
// non-finite number, an interval out of [min_interval, max_interval], a
// displacement beyond 1e4 px or a gradient beyond 1e3 per frame, a
// covariance of the displacement that is not positive definite or beyond
// (1e4 px)^2.
std::string checkFlow(const FlowMeasurement& f, double min_interval, double max_interval);

// The predicted displacement and its linearisation in e.
struct FlowPrediction {
  Vec2 displacement = Vec2::Zero();  // [px]
  Mat23 H = Mat23::Zero();           // d displacement / d e [px per m/s]
  Mat2 R_geometry = Mat2::Zero();    // the depth's share of the noise [px^2]
};

// X0 = geometry0.point() is the skin point on the flow pixel's ray at t_prev
// (camera frame at t_prev); T_c1_c0 the camera's motion over the interval
// (the odometry's twist integrated); e the extra skin velocity (camera frame at t):
//   X1 = T_c1_c0 X0 + e (t - t_prev),  displacement = pi(X1) - pi(X0)
// with pi the raw-pixel projection (the flow is measured on raw images).
FlowPrediction predictFlow(const RayGeometry& geometry0, const Eigen::Isometry3d& T_c1_c0, const Vec3& e, double dt,
                           const ImagingCamera& cam);

}  // namespace surface_motion
}  // namespace hapi_eskf
