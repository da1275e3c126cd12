// The velocity map (docs/DESIGN.md "Surface motion", definitions): from the
// camera's twist relative to the surface, the extra relative velocity e, the
// pixel's ray, the depth along it and the surface normal, the skin point,
// its material velocity, the on-surface velocity (oblique projection along
// the ray onto the tangent plane), the normal velocity and the image
// velocity, each with its covariance by first-order propagation through the
// analytic Jacobian (checked against central differences in
// test/test_surface_motion_velocity_map.cpp).
#pragma once

#include "hapi_eskf/surface_motion/imaging_camera.hpp"

namespace hapi_eskf {
namespace surface_motion {

using Mat4 = Eigen::Matrix4d;

// The surface where the pixel's ray meets it (surface_fit.hpp finds it).
struct RayGeometry {
  Vec3 ray = Vec3::UnitZ();       // unit ray of the pixel, camera frame
  double depth = 0;               // [m] along the ray: X = depth * ray
  Vec3 normal = -Vec3::UnitZ();   // unit, towards the camera (normal . ray < 0)
  Mat4 covariance = Mat4::Zero(); // of (depth, normal) [m^2, m, 1]
  Vec3 point() const { return depth * ray; }
};

// The map's inputs, q = [v (3), w (3), e (3), depth (1), normal (3)]:
// camera twist relative to the surface in the camera frame [m/s, rad/s],
// e the skin's velocity the twist does not explain [m/s], and the geometry.
constexpr int kMapInputs = 13;
// Its outputs, y = [X (3), s (3), normal velocity (1), image velocity (2)]
// in SI units (m, m/s, m/s, px/s).
constexpr int kMapOutputs = 9;
using MapInput = Eigen::Matrix<double, kMapInputs, 1>;
using MapOutput = Eigen::Matrix<double, kMapOutputs, 1>;
using MapJacobian = Eigen::Matrix<double, kMapOutputs, kMapInputs>;
using MapInputCovariance = Eigen::Matrix<double, kMapInputs, kMapInputs>;

MapInput mapInput(const Vec3& v, const Vec3& w, const Vec3& e, const RayGeometry& g);

// Material velocity Xdot = -(v + w x X) + e at X = depth * ray.
Vec3 materialVelocity(const Vec3& v, const Vec3& w, const Vec3& e, const Vec3& X);

// y(q) for the pixel's ray `ray` (pinhole image velocity, DESIGN).
MapOutput evaluateVelocityMap(const MapInput& q, const Vec3& ray, const ImagingCamera& cam);
// dy/dq, analytic.
MapJacobian velocityMapJacobian(const MapInput& q, const Vec3& ray, const ImagingCamera& cam);

// What the message carries, in its units: m, mm/s, px/frame.
struct SurfaceVelocity {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::Zero();
  Vec3 surface_velocity = Vec3::Zero();  // [mm/s]
  Mat3 surface_velocity_covariance = Mat3::Zero();
  double normal_velocity = 0, normal_velocity_variance = 0;  // [mm/s], [(mm/s)^2]
  Vec2 image_velocity = Vec2::Zero();  // [px/frame]
  Mat2 image_velocity_covariance = Mat2::Zero();
  double speed() const { return surface_velocity.norm(); }
};

// The map and its first-order covariance, C_y = J C_q J^T, C_q the inputs'
// covariance (its depth/normal block is usually g.covariance).
SurfaceVelocity mapVelocity(const MapInput& q, const MapInputCovariance& Cq, const Vec3& ray,
                            const ImagingCamera& cam);

}  // namespace surface_motion
}  // namespace hapi_eskf
