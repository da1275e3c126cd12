// TSDF fusion and meshing of rendered depth: the mesh of a known plane and
// a known sphere lies within stated distances of the true surface, its
// normals point to the cameras, and a rebuild after a pose correction gives
// the volume of the corrected poses bit for bit.
#include "hapi_surface/mesh_extraction.hpp"
#include "hapi_surface/surface_mapper.hpp"

#include "synthetic_scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace hapi_surface {
namespace {

using test::lookAt;
using test::Scene;
using test::testCamera;

// A 6 x 6 x 3 cm volume at 0.5 mm (120 x 120 x 60 voxels).
SurfaceSettings smallVolume() { return test::volumeOf(0.06, 0.06, 0.03); }

struct MeshError {
  double rms = 0, max = 0, normal_dot_mean = 0;
  std::size_t n = 0;
};

// Distance and normal agreement of every vertex with the true surface.
MeshError compare(const Mesh& m, const std::function<double(const Eigen::Vector3d&)>& distance,
                  const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& normal) {
  MeshError e;
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    const Eigen::Vector3d p = m.vertices[i].cast<double>();
    const double d = distance(p);
    e.rms += d * d;
    e.max = std::max(e.max, std::abs(d));
    e.normal_dot_mean += m.normals[i].cast<double>().dot(normal(p));
  }
  e.n = m.vertices.size();
  if (e.n > 0) {
    e.rms = std::sqrt(e.rms / e.n);
    e.normal_dot_mean /= e.n;
  }
  return e;
}

TsdfVolume fuse(const Scene& scene, const std::vector<Eigen::Isometry3d>& poses, const Eigen::Vector3d& centre,
                const SurfaceSettings& s) {
  TsdfVolume vol(VoxelGrid::centredAt(centre, s), s);
  for (const auto& T : poses) {
    DepthFrame f;
    f.camera = testCamera();
    f.T_world_camera = T;
    f.depth = scene.depth(f.camera, T);
    EXPECT_EQ(vol.integrate(f), SurfaceStatus::kOk);
  }
  return vol;
}

TEST(TsdfMesh, TiltedPlaneWithinATenthOfAVoxel) {
  // The plane through (0, 0, 0.25) tilted 20 degrees about y, seen from 3 poses.
  const Eigen::Vector3d n(std::sin(0.35), 0, -std::cos(0.35));
  const Eigen::Vector3d c(0, 0, 0.25);
  Scene scene;
  scene.addPlane(n, n.dot(c));
  const std::vector<Eigen::Isometry3d> poses = {lookAt({0, 0, 0}, c), lookAt({0.01, 0, 0.005}, c),
                                                lookAt({-0.01, 0.01, 0}, c)};
  const TsdfVolume vol = fuse(scene, poses, c, smallVolume());
  const Mesh m = extractMesh(vol);
  ASSERT_GT(m.faces.size(), 10000u);
  const MeshError e = compare(m, [&](const Eigen::Vector3d& p) { return n.dot(p - c); },
                              [&](const Eigen::Vector3d&) { return n; });
  std::printf("plane: %zu vertices, %zu faces, RMS %.4f mm, max %.4f mm, mean normal . true %.5f\n", e.n,
              m.faces.size(), e.rms * 1e3, e.max * 1e3, e.normal_dot_mean);
  EXPECT_LT(e.rms, 0.05e-3);  // a tenth of a voxel
  EXPECT_LT(e.max, 0.2e-3);
  EXPECT_GT(e.normal_dot_mean, 0.99);  // towards the cameras (n points to them)
}

TEST(TsdfMesh, SphereWithinAQuarterVoxel) {
  // A 2 cm radius sphere at 25 cm, seen from 5 poses around its front.
  const Eigen::Vector3d c(0, 0, 0.25);
  const double r = 0.02;
  Scene scene;
  scene.addSphere(c, r);
  std::vector<Eigen::Isometry3d> poses;
  for (int i = 0; i < 5; ++i) {
    const double a = 0.3 * (i - 2);
    poses.push_back(lookAt(c + 0.23 * Eigen::Vector3d(std::sin(a), 0.1 * i - 0.2, -std::cos(a)), c));
  }
  const SurfaceSettings s = test::volumeOf(0.06, 0.06, 0.05);
  const TsdfVolume vol = fuse(scene, poses, c, s);
  const Mesh m = extractMesh(vol);
  ASSERT_GT(m.faces.size(), 10000u);
  const MeshError e = compare(m, [&](const Eigen::Vector3d& p) { return (p - c).norm() - r; },
                              [&](const Eigen::Vector3d& p) { return Eigen::Vector3d((p - c).normalized()); });
  std::printf("sphere: %zu vertices, %zu faces, RMS %.4f mm, max %.4f mm, mean normal . true %.5f\n", e.n,
              m.faces.size(), e.rms * 1e3, e.max * 1e3, e.normal_dot_mean);
  EXPECT_LT(e.rms, 0.125e-3);  // a quarter voxel
  EXPECT_LT(e.max, 0.5e-3);
  EXPECT_GT(e.normal_dot_mean, 0.97);
}

TEST(TsdfMesh, SharedVerticesAndClosedSurfaceInside) {
  Scene scene;
  const Eigen::Vector3d c(0, 0, 0.25);
  scene.addPlane(Eigen::Vector3d(0, 0, -1), -0.25);
  const TsdfVolume vol = fuse(scene, {lookAt({0, 0, 0}, c)}, c, smallVolume());
  const Mesh m = extractMesh(vol);
  ASSERT_FALSE(m.empty());
  // Every vertex is used, and (away from the border) by several triangles.
  std::vector<int> uses(m.vertices.size(), 0);
  for (const auto& f : m.faces)
    for (int v : f) ++uses[v];
  std::size_t shared = 0;
  for (int u : uses) {
    EXPECT_GT(u, 0);
    shared += u >= 3;
  }
  EXPECT_GT(shared, m.vertices.size() * 9 / 10);
  // Each triangle's winding agrees with its vertices' normals.
  for (const auto& f : m.faces) {
    const Eigen::Vector3f g = (m.vertices[f[1]] - m.vertices[f[0]]).cross(m.vertices[f[2]] - m.vertices[f[0]]);
    ASSERT_GE(g.dot(m.normals[f[0]] + m.normals[f[1]] + m.normals[f[2]]), 0.f);
  }
}

TEST(TsdfMesh, RebuildAfterPoseCorrectionEqualsFusionAtCorrectedPoses) {
  const Eigen::Vector3d c(0, 0, 0.25);
  Scene scene;
  scene.addSphere(c + Eigen::Vector3d(0, 0, 0.02), 0.025);
  const std::vector<Eigen::Isometry3d> truth = {lookAt({0, 0, 0}, c), lookAt({0.01, 0, 0}, c),
                                                lookAt({0.02, 0.005, 0}, c)};
  const SurfaceSettings s = smallVolume();
  auto run = [&](const std::vector<Eigen::Isometry3d>& believed, SurfaceMapper* m) {
    for (std::size_t i = 0; i < truth.size(); ++i) {
      DepthFrame f;
      f.camera = testCamera();
      f.depth = scene.depth(f.camera, truth[i]);
      FrameUse use;
      ASSERT_EQ(m->addDepthFrame(static_cast<double>(i), f, believed[i], &use), SurfaceStatus::kOk);
      ASSERT_EQ(use, FrameUse::kKeyframe);
    }
  };
  SurfaceMapper right(s), wrong(s);
  run(truth, &right);
  std::vector<Eigen::Isometry3d> drifted = truth;
  drifted[2].translation() += Eigen::Vector3d(0.002, 0, 0);  // 2 mm of drift on the last keyframe
  run(drifted, &wrong);
  ASSERT_NE(wrong.volume()->tsdf(), right.volume()->tsdf());
  auto truth_at = [&](double t, const Eigen::Isometry3d&) {
    return std::optional<Eigen::Isometry3d>(truth[static_cast<int>(t)]);
  };
  // Corrections below the threshold change nothing.
  EXPECT_FALSE(right.correctPoses(truth_at));
  EXPECT_TRUE(wrong.correctPoses(truth_at));
  EXPECT_EQ(wrong.rebuilds(), 1u);
  EXPECT_EQ(wrong.volume()->tsdf(), right.volume()->tsdf());
  EXPECT_EQ(wrong.volume()->weight(), right.volume()->weight());
  EXPECT_EQ(wrong.mesh().faces.size(), right.mesh().faces.size());
}

TEST(TsdfMesh, KeyframesOnlyAfterMotionOrTime) {
  const Eigen::Vector3d c(0, 0, 0.25);
  Scene scene;
  scene.addPlane(Eigen::Vector3d(0, 0, -1), -0.25);
  SurfaceMapper m(smallVolume());
  DepthFrame f;
  f.camera = testCamera();
  f.depth = scene.depth(f.camera, Eigen::Isometry3d::Identity());
  FrameUse use;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  ASSERT_EQ(m.addDepthFrame(0.0, f, T, &use), SurfaceStatus::kOk);
  EXPECT_EQ(use, FrameUse::kKeyframe);
  T.translation().x() = 0.001;  // 1 mm < keyframe_translation, 0.1 s < keyframe_interval
  ASSERT_EQ(m.addDepthFrame(0.1, f, T, &use), SurfaceStatus::kOk);
  EXPECT_EQ(use, FrameUse::kSkipped);
  T.translation().x() = 0.004;
  ASSERT_EQ(m.addDepthFrame(0.2, f, T, &use), SurfaceStatus::kOk);
  EXPECT_EQ(use, FrameUse::kKeyframe);
  ASSERT_EQ(m.addDepthFrame(1.3, f, T, &use), SurfaceStatus::kOk);
  EXPECT_EQ(use, FrameUse::kKeyframe);
  EXPECT_EQ(m.keyframes().size(), 3u);
}


}  // namespace
}  // namespace hapi_surface
