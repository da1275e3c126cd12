// Depth and normal at the pixel's ray from the map (docs/DESIGN.md "Surface
// motion", depth): the landmarks seen by the imaging camera at its pose,
// those projecting within a radius of the pixel (the radius doubling up to
// its maximum until enough are found), a robust plane fit (plane_fit.hpp),
// and the ray's intersection with that plane, with covariance.
#pragma once

#include "hapi_eskf/surface_motion/imaging_camera.hpp"
#include "hapi_eskf/surface_motion/surface_motion_settings.hpp"
#include "hapi_eskf/surface_motion/velocity_map.hpp"

#include <string>
#include <vector>

namespace hapi_eskf {
namespace surface_motion {

// The message's statuses (hapi_msgs/SurfaceMotion), the same numbers.
enum class MotionStatus : uint8_t { kOk = 0, kNoPose = 1, kNoDepth = 2, kRayMissesMap = 3, kNoExtrinsic = 4 };
const char* toString(MotionStatus s);

struct RaySurface {
  MotionStatus status = MotionStatus::kNoDepth;
  std::string message;     // why, when not OK
  RayGeometry geometry;    // valid when OK
  int landmarks = 0;       // fitted (near the ray)
  double radius = 0;       // [px] the radius they were found within
};

// `landmarks_world`: the map (world frame); T_world_cam: the imaging camera's
// pose; `ray`: the pixel's unit ray (ImagingCamera::ray).
//  * fewer than min_landmarks in the map: NO_DEPTH;
//  * none in front of the camera within max_search_radius of the pixel:
//    RAY_MISSES_MAP; some, but fewer than min_landmarks: NO_DEPTH;
//  * a degenerate fit, a ray grazing the plane (|n . r| < min_incidence_cosine)
//    or a plane behind the camera: NO_DEPTH.
RaySurface surfaceAtRay(const std::vector<Vec3>& landmarks_world, const Eigen::Isometry3d& T_world_cam,
                        const ImagingCamera& cam, const Vec3& ray, const SurfaceMotionSettings& s);

}  // namespace surface_motion
}  // namespace hapi_eskf
