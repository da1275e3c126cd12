// hapi_sim: the true surface motion at one pixel of the imaging camera
// (docs/DESIGN.md "Data", "Surface-motion truth"): where the pixel's ray
// meets the scene, the surface normal there, and how the scene's material
// point on the ray moves relative to the camera, in the units of
// hapi_msgs/SurfaceMotion. Exact: the ray-surface intersection of the
// scene's geometry and the motion's exact derivatives (Jet2). ROS-free.
#pragma once
#include <Eigen/Core>

#include "hapi_sim/globe_sim.hpp"
#include "hapi_sim/motion.hpp"
#include "hapi_sim/scene.hpp"

namespace hapi_sim {

// Every vector is in the camera's optical frame.
struct SurfaceMotionTruth {
  bool hit = false;  // false: the pixel's ray misses the scene (the rest is zero)
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();           // px
  double frame_rate = 0.0;                                   // Hz, the camera's
  Eigen::Vector3d point = Eigen::Vector3d::Zero();           // m, X = d r on the surface
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();          // unit, towards the camera (n . r < 0)
  Eigen::Vector3d surface_velocity = Eigen::Vector3d::Zero();  // mm/s, s = Xdot - r (Xdot . n) / (r . n)
  double speed = 0.0;                                        // mm/s, |s|
  double normal_velocity = 0.0;                              // mm/s, Xdot . n (> 0: approaching)
  Eigen::Vector2d image_velocity = Eigen::Vector2d::Zero();  // px per frame, d/dt pi(X) / frame_rate
  // hapi_msgs/SurfaceMotion's status codes (the bag writer checks they agree).
  static constexpr int kStatusOk = 0, kStatusRayMissesMap = 3;
  int status() const { return hit ? kStatusOk : kStatusRayMissesMap; }
};

// The truth at `pixel` of `camera` (pi its projection, lens distortion
// included) moving relative to the scene as `camera_in_scene` (pose of the
// optical frame in the scene frame, velocity in the scene frame, angular
// velocity in the optical frame: relativeMotion's sample). The material
// point's velocity in the camera frame is Xdot = -(v_c + w_c x X).
SurfaceMotionTruth surfaceMotionTruth(const Scene& scene, const CameraModel& camera, const Eigen::Vector2d& pixel,
                                      double frame_rate, const MotionSample& camera_in_scene);

}  // namespace hapi_sim
