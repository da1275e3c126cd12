#include "hapi_eskf/surface_motion/ray_surface.hpp"

#include "hapi_eskf/surface_motion/plane_fit.hpp"

#include <algorithm>
#include <cmath>

namespace hapi_eskf {
namespace surface_motion {

const char* toString(MotionStatus s) {
  switch (s) {
    case MotionStatus::kOk: return "ok";
    case MotionStatus::kNoPose: return "no pose";
    case MotionStatus::kNoDepth: return "no depth";
    case MotionStatus::kRayMissesMap: return "ray misses map";
    case MotionStatus::kNoExtrinsic: return "no extrinsic";
  }
  return "?";
}

namespace {

RaySurface fail(MotionStatus st, std::string why, int n, double radius) {
  RaySurface out;
  out.status = st;
  out.message = std::move(why);
  out.landmarks = n;
  out.radius = radius;
  return out;
}

// The ray's intersection with the fitted plane: depth = c / (n . r), with
// the normal turned towards the camera, and the covariance of (depth, n)
// from the fit's (a, b, c).
RaySurface intersect(const PlaneFit& f, const Vec3& ray, const SurfaceMotionSettings& s, int n, double radius) {
  Vec3 nrm = f.normal, t1 = f.t1, t2 = f.t2;
  double c = f.offset;
  Mat3 C = f.covariance;
  if (nrm.dot(ray) > 0) {
    // Towards the camera (n . r < 0): -(n + a t1 + b t2) = n' + a t1' + b t2'
    // with t' = -t, and c' = -c moves by -dc.
    nrm = -nrm;
    c = -c;
    t1 = -t1;
    t2 = -t2;
    const Eigen::DiagonalMatrix<double, 3> D(1, 1, -1);
    C = D * C * D;
  }
  const double b = nrm.dot(ray);
  if (-b < s.min_incidence_cosine)
    return fail(MotionStatus::kNoDepth, "the ray grazes the surface (|n . r| " + std::to_string(-b) + ")", n, radius);
  const double depth = c / b;
  if (!(depth > s.min_depth)) return fail(MotionStatus::kNoDepth, "the fitted surface is behind the camera", n, radius);
  // d(depth)/d(a, b, c) with n(a, b) = n + a t1 + b t2; dn/d(a, b) = [t1 t2].
  Eigen::Matrix<double, 4, 3> G = Eigen::Matrix<double, 4, 3>::Zero();
  G(0, 0) = -c * t1.dot(ray) / (b * b);
  G(0, 1) = -c * t2.dot(ray) / (b * b);
  G(0, 2) = 1.0 / b;
  G.block<3, 1>(1, 0) = t1;
  G.block<3, 1>(1, 1) = t2;
  RaySurface out;
  out.status = MotionStatus::kOk;
  out.geometry.ray = ray;
  out.geometry.depth = depth;
  out.geometry.normal = nrm;
  out.geometry.covariance = G * C * G.transpose();
  out.landmarks = n;
  out.radius = radius;
  return out;
}

}  // namespace

RaySurface surfaceAtRay(const std::vector<Vec3>& landmarks_world, const Eigen::Isometry3d& T_world_cam,
                        const ImagingCamera& cam, const Vec3& ray, const SurfaceMotionSettings& s) {
  const int total = static_cast<int>(landmarks_world.size());
  if (total < s.min_landmarks)
    return fail(MotionStatus::kNoDepth,
                "the map has " + std::to_string(total) + " landmarks, the fit needs " + std::to_string(s.min_landmarks),
                0, 0);
  // Distances in ideal (undistorted) pixels from the pixel's ray.
  const Vec2 at(cam.fx * ray.x() / ray.z() + cam.cx, cam.fy * ray.y() / ray.z() + cam.cy);
  const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
  std::vector<Vec3> pts;
  std::vector<double> dist;
  pts.reserve(landmarks_world.size());
  dist.reserve(landmarks_world.size());
  for (const Vec3& Xw : landmarks_world) {
    const Vec3 X = T_cam_world * Xw;
    if (!(X.z() > s.min_depth)) continue;
    const double d = (cam.projectPinhole(X) - at).norm();
    if (d <= s.max_search_radius) {
      pts.push_back(X);
      dist.push_back(d);
    }
  }
  // Widen: the radius doubles from search_radius until min_landmarks lie
  // within it or it reaches max_search_radius.
  double radius = s.search_radius;
  std::vector<Vec3> near;
  for (;;) {
    near.clear();
    for (std::size_t i = 0; i < pts.size(); ++i)
      if (dist[i] <= radius) near.push_back(pts[i]);
    if (static_cast<int>(near.size()) >= s.min_landmarks || radius >= s.max_search_radius) break;
    radius = std::min(2 * radius, s.max_search_radius);
  }
  const int n = static_cast<int>(near.size());
  if (n == 0)
    return fail(MotionStatus::kRayMissesMap,
                "no landmark within " + std::to_string(static_cast<int>(radius)) + " px of the pixel", 0, radius);
  if (n < s.min_landmarks)
    return fail(MotionStatus::kNoDepth,
                std::to_string(n) + " landmarks within " + std::to_string(static_cast<int>(radius)) +
                    " px of the pixel, the fit needs " + std::to_string(s.min_landmarks),
                n, radius);
  const PlaneFit f = fitPlane(near, s.plane_huber_k, s.plane_iterations, s.plane_sigma_floor);
  if (!f.ok) return fail(MotionStatus::kNoDepth, "the landmarks near the ray fit no plane", n, radius);
  return intersect(f, ray, s, n, radius);
}

}  // namespace surface_motion
}  // namespace hapi_eskf
