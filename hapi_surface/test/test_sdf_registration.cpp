// Registration of a depth frame to the fused surface (sdf_registration.hpp):
// the interpolated distance and gradient of a known plane, a pose a few
// millimetres and a degree off brought back near the true one, and a frame
// far outside the truncation band refused.
#include "hapi_surface/sdf_registration.hpp"

#include "two_balls_scene.hpp"

#include <gtest/gtest.h>

namespace hapi_surface {
namespace {

using test::TwoBalls;

TsdfVolume fuseTruth(const TwoBalls& b, const SurfaceSettings& s) {
  const test::Scene scene = b.scene();
  TsdfVolume vol(VoxelGrid::centredAt(b.centre, s), s);
  for (const auto& T : b.cameras(6)) {
    DepthFrame f;
    f.camera = test::testCamera();
    f.T_world_camera = T;
    f.depth = scene.depth(f.camera, T);
    EXPECT_EQ(vol.integrate(f), SurfaceStatus::kOk);
  }
  return vol;
}

DepthFrame frameAt(const TwoBalls& b, const Eigen::Isometry3d& truth, const Eigen::Isometry3d& believed) {
  DepthFrame f;
  f.camera = test::testCamera();
  f.depth = b.scene().depth(f.camera, truth);
  f.T_world_camera = believed;
  return f;
}

TEST(SdfRegistration, DistanceAndGradientOfAPlane) {
  TwoBalls b;
  const SurfaceSettings s = TwoBalls::settings();
  const TsdfVolume vol = fuseTruth(b, s);
  // 2 mm in front of the plane, away from the balls: distance 2 mm, the
  // gradient towards the cameras (-z).
  double d;
  Eigen::Vector3d g;
  ASSERT_TRUE(sampleSignedDistance(vol, Eigen::Vector3d(0.0, 0.025, b.plane_z - 0.002), &d, &g));
  EXPECT_NEAR(d, 0.002, 0.1e-3);
  EXPECT_NEAR(g.z(), -1.0, 0.05);
  EXPECT_NEAR(g.head<2>().norm(), 0.0, 0.05);
  // Outside the grid, and far in front (clipped): no sample.
  EXPECT_FALSE(sampleSignedDistance(vol, Eigen::Vector3d(1, 1, 1), &d, &g));
  EXPECT_FALSE(sampleSignedDistance(vol, Eigen::Vector3d(0.0, 0.025, b.plane_z - 0.02), &d, &g));
}

TEST(SdfRegistration, BringsAnOffsetPoseBack) {
  TwoBalls b;
  const TsdfVolume vol = fuseTruth(b, TwoBalls::settings());
  const Eigen::Isometry3d truth = test::lookAt(Eigen::Vector3d(0.01, -0.015, 0.005), b.centre);
  const Eigen::Isometry3d off = test::perturbed(truth, Eigen::Vector3d(0.002, -0.0015, 0.0025), 0.015,
                                               Eigen::Vector3d(1, 2, 0.5));
  const Registration r = registerToSurface(vol, frameAt(b, truth, off));
  ASSERT_TRUE(r.accepted) << "median " << r.median_distance << " points " << r.points;
  const double before = translationBetween(off, truth), after = translationBetween(r.T_world_camera, truth);
  std::printf("registration: %zu points, %d iterations, median %.4f mm; offset %.3f mm, %.3f deg -> %.4f mm, %.4f deg\n",
              r.points, r.iterations, r.median_distance * 1e3, before * 1e3, rotationBetween(off, truth) * 180 / M_PI,
              after * 1e3, rotationBetween(r.T_world_camera, truth) * 180 / M_PI);
  // The frame's points land on the surface (median below); the pose is
  // within a tenth of its offset (the balls constrain the rotation about
  // the view axis least).
  EXPECT_LT(after, 0.15e-3);
  EXPECT_LT(rotationBetween(r.T_world_camera, truth), 0.1 * M_PI / 180);
  EXPECT_LT(r.median_distance, 0.1e-3);
  EXPECT_EQ(checkPose(r.T_world_camera), SurfaceStatus::kOk);
}

TEST(SdfRegistration, RefusesAFrameFarOffTheSurface) {
  TwoBalls b;
  const TsdfVolume vol = fuseTruth(b, TwoBalls::settings());
  const Eigen::Isometry3d truth = test::lookAt(Eigen::Vector3d(0.0, 0.01, 0.0), b.centre);
  // 3 cm nearer: its points lie beyond the truncation band.
  const Registration r = registerToSurface(vol, frameAt(b, truth, test::perturbed(truth, Eigen::Vector3d(0, 0, 0.03), 0,
                                                                                   Eigen::Vector3d::UnitZ())));
  EXPECT_FALSE(r.accepted);
}

}  // namespace
}  // namespace hapi_surface
