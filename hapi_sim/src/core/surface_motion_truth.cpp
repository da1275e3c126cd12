// The surface-motion truth (surface_motion_truth.hpp): intersection, normal,
// material velocity, its oblique projection on the tangent plane and its
// image motion through the camera's projection evaluated on jets.
#include "hapi_sim/surface_motion_truth.hpp"

#include "hapi_sim/jet.hpp"

namespace hapi_sim {
namespace {

constexpr double kMmPerM = 1e3;

// d/dt of the distorted pixel of X(t) with X(0) = X, X'(0) = Xdot [px/s].
Eigen::Vector2d pixelRate(const CameraModel& c, const Eigen::Vector3d& X, const Eigen::Vector3d& Xdot) {
  const Jet2 x(X.x(), Xdot.x(), 0.0), y(X.y(), Xdot.y(), 0.0), z(X.z(), Xdot.z(), 0.0);
  Jet2 xd, yd;
  distortNormalized(c, x / z, y / z, &xd, &yd);
  return {c.fx * xd.d, c.fy * yd.d};
}

}  // namespace

SurfaceMotionTruth surfaceMotionTruth(const Scene& scene, const CameraModel& camera, const Eigen::Vector2d& pixel,
                                      double frame_rate, const MotionSample& camera_in_scene) {
  SurfaceMotionTruth m;
  m.pixel = pixel;
  m.frame_rate = frame_rate;
  const Eigen::Vector3d r = pixelToRay(camera, pixel);
  const Eigen::Matrix3d R = camera_in_scene.q.toRotationMatrix();
  double depth;
  Eigen::Vector3d n_scene;
  if (!intersectSurfaces(scene.surfaces(), camera_in_scene.p, R * r, &depth, &n_scene)) return m;
  m.hit = true;
  m.point = depth * r;
  m.normal = R.transpose() * n_scene;
  const Eigen::Vector3d v_c = R.transpose() * camera_in_scene.v;
  const Eigen::Vector3d Xdot = -(v_c + camera_in_scene.omega.cross(m.point));
  const Eigen::Vector3d s = Xdot - r * (Xdot.dot(m.normal) / r.dot(m.normal));
  m.surface_velocity = kMmPerM * s;
  m.speed = m.surface_velocity.norm();
  m.normal_velocity = kMmPerM * Xdot.dot(m.normal);
  m.image_velocity = pixelRate(camera, m.point, Xdot) / frame_rate;
  return m;
}

}  // namespace hapi_sim
