// Depth and normal at the pixel's ray from the map (docs/DESIGN.md "Surface
// motion", depth): the robust plane fit, the radius rule and the statuses.
#include "hapi_eskf/surface_motion/ray_surface.hpp"

#include "hapi_eskf/so3.hpp"
#include "surface_motion_scene.hpp"

#include <gtest/gtest.h>

#include <random>

namespace hapi_eskf {
namespace surface_motion {
namespace {

using test::testCamera;

// A tilted plane through (0, 0, depth) seen from a rotated, shifted camera,
// with noisy landmarks and gross outliers: depth and normal recovered, and
// the errors consistent with the stated covariance over many draws.
TEST(SurfaceMotionGeometry, RobustPlaneFitRecoversDepthAndNormal) {
  const ImagingCamera cam = testCamera();
  SurfaceMotionSettings s;
  const Vec3 n_world = Vec3(0.2, -0.1, -1).normalized();
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
  T_world_cam.linear() = expSO3(Vec3(0.05, -0.1, 0.2));
  T_world_cam.translation() = Vec3(0.01, -0.02, 0.03);
  const Vec3 ray = cam.ray(Vec2(350, 220));
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 5e-4);
  std::uniform_real_distribution<double> uni(-1, 1);
  double nees = 0;
  const int draws = 200;
  for (int k = 0; k < draws; ++k) {
    std::vector<Vec3> lms;
    const Vec3 c(0, 0, 0.3), t1 = n_world.unitOrthogonal(), t2 = n_world.cross(t1);
    for (int i = 0; i < 150; ++i) lms.push_back(c + 0.1 * uni(rng) * t1 + 0.1 * uni(rng) * t2 + noise(rng) * n_world);
    // 3 % gross outliers (a hair, a mismatched landmark) 3 cm off the skin.
    for (int i = 0; i < 5; ++i) lms.push_back(c + 0.1 * uni(rng) * t1 + 0.1 * uni(rng) * t2 + 0.03 * n_world);
    const RaySurface rs = surfaceAtRay(lms, T_world_cam, cam, ray, s);
    ASSERT_EQ(rs.status, MotionStatus::kOk) << rs.message;
    // Truth: the ray in the world meets the plane n . (X - c) = 0.
    const Vec3 o = T_world_cam.translation(), dw = T_world_cam.linear() * ray;
    const double depth = n_world.dot(c - o) / n_world.dot(dw);
    const Vec3 n_cam = T_world_cam.linear().transpose() * n_world;  // towards the camera
    ASSERT_LT(rs.geometry.normal.dot(ray), 0);
    // Within 5 sigma (depth) and 5 sigma of the normal's tangent error.
    const double ed = rs.geometry.depth - depth;
    const double sd = std::sqrt(rs.geometry.covariance(0, 0));
    EXPECT_LT(std::abs(ed), 5 * sd) << "draw " << k << ", " << rs.landmarks << " landmarks within " << rs.radius;
    const Vec3 en = rs.geometry.normal - n_cam;
    EXPECT_LT(en.norm(), 5 * std::sqrt(rs.geometry.covariance.bottomRightCorner<3, 3>().trace()) + 1e-3)
        << "draw " << k << ", " << rs.landmarks << " landmarks within " << rs.radius;
    EXPECT_LT(sd, 1e-3);
    nees += ed * ed / (sd * sd);
  }
  // The depth's mean NEES (1 dof): chi^2 200 / 200 95 % band [0.81, 1.21],
  // widened for the robust weights' approximation.
  EXPECT_GT(nees / draws, 0.6);
  EXPECT_LT(nees / draws, 1.6);
}

TEST(SurfaceMotionGeometry, StatusesNoDepthAndRayMissesMap) {
  const ImagingCamera cam = testCamera();
  SurfaceMotionSettings s;
  const Vec3 ray = cam.ray(cam.pixel(-1, -1));
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  // No map.
  EXPECT_EQ(surfaceAtRay({}, I, cam, ray, s).status, MotionStatus::kNoDepth);
  // Plenty of landmarks, all far from the ray (> max_search_radius px): misses.
  std::vector<Vec3> far;
  for (int i = 0; i < 30; ++i) far.emplace_back(0.2 + 0.001 * i, 0.1, 0.3);  // ~330 px right of centre
  EXPECT_EQ(surfaceAtRay(far, I, cam, ray, s).status, MotionStatus::kRayMissesMap);
  // Behind the camera: as far as the ray is concerned, nothing.
  std::vector<Vec3> behind;
  for (int i = 0; i < 30; ++i) behind.emplace_back(0.001 * i, 0.0, -0.3);
  EXPECT_EQ(surfaceAtRay(behind, I, cam, ray, s).status, MotionStatus::kRayMissesMap);
  // A few near the ray, not enough for a fit: no depth.
  std::vector<Vec3> few = far;
  for (int i = 0; i < s.min_landmarks - 1; ++i) few.emplace_back(0.002 * i, 0.001 * (i % 2), 0.3);
  const RaySurface rs = surfaceAtRay(few, I, cam, ray, s);
  EXPECT_EQ(rs.status, MotionStatus::kNoDepth);
  EXPECT_FALSE(rs.message.empty());
}

TEST(SurfaceMotionGeometry, RadiusWidensUntilEnoughLandmarks) {
  const ImagingCamera cam = testCamera();
  SurfaceMotionSettings s;
  s.max_search_radius = 160;  // 40 px, doubling to 160 px
  std::vector<Vec3> ring;   // a ring about 100 px from the pixel (0.06 m at 0.3 m)
  for (int i = 0; i < 12; ++i) {
    const double a = 2 * M_PI * i / 12;
    ring.emplace_back(0.06 * std::cos(a), 0.06 * std::sin(a), 0.3 + 0.01 * std::cos(a));
  }
  const RaySurface rs = surfaceAtRay(ring, Eigen::Isometry3d::Identity(), cam, Vec3::UnitZ(), s);
  ASSERT_EQ(rs.status, MotionStatus::kOk) << rs.message;
  EXPECT_DOUBLE_EQ(rs.radius, 160.0);  // 40 -> 80 (none) -> 160
  EXPECT_NEAR(rs.geometry.depth, 0.3, 1e-9);
  s.max_search_radius = 80;
  EXPECT_EQ(surfaceAtRay(ring, Eigen::Isometry3d::Identity(), cam, Vec3::UnitZ(), s).status,
            MotionStatus::kRayMissesMap);
}

TEST(SurfaceMotionGeometry, SettingsTableValidates) {
  SurfaceMotionSettings s;
  EXPECT_EQ(s.validate(), "");
  s.max_search_radius = 10;
  EXPECT_NE(s.validate(), "");
  s = SurfaceMotionSettings();
  s.min_landmarks = 2;
  EXPECT_NE(s.validate().find("min_landmarks"), std::string::npos);
}

}  // namespace
}  // namespace surface_motion
}  // namespace hapi_eskf
