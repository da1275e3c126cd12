// Projection of imaging frames onto the mesh: a known pattern painted on a
// plane comes back at the vertices; vertices hidden from the imaging camera
// by a ball in front get no value; frames average with their weights; a
// camera with lens distortion puts the pattern in place only when the
// projection applies the distortion.
#include "hapi_surface/mesh_depth_render.hpp"
#include "hapi_surface/surface_mapper.hpp"

#include "synthetic_scene.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace hapi_surface {
namespace {

using test::lookAt;
using test::Scene;
using test::testCamera;

const Eigen::Vector3d kCentre(0, 0, 0.25);

// The background plane z = 0.26 and a ball of 8 mm radius 1.2 cm in front.
const Eigen::Vector3d kBall(0, 0, 0.24);
constexpr double kBallRadius = 0.008;
Scene ballScene() {
  Scene s;
  s.addPlane(Eigen::Vector3d(0, 0, 1), 0.26);
  s.addSphere(kBall, kBallRadius);
  return s;
}

double pattern(const Eigen::Vector3d& p) { return 100.0 + 1000.0 * p.x() + 300.0 * p.y(); }

SurfaceSettings settings() { return test::volumeOf(0.07, 0.07, 0.06); }

// A mapper fed with depth from 5 cameras spread over 4 cm, so the background
// behind the ball is observed.
SurfaceMapper mapScene(const Scene& scene) {
  SurfaceMapper m(settings());
  const Eigen::Vector3d positions[] = {{0, 0, 0}, {0.04, 0, 0}, {-0.04, 0, 0}, {0, 0.04, 0}, {0, -0.04, 0}};
  double t = 0;
  for (const auto& pos : positions) {
    DepthFrame f;
    f.camera = testCamera();
    const Eigen::Isometry3d T = lookAt(pos, kCentre);
    f.depth = scene.depth(f.camera, T);
    FrameUse use;
    EXPECT_EQ(m.addDepthFrame(t++, f, T, &use), SurfaceStatus::kOk);
  }
  return m;
}

// Distance of the ball's centre from the segment p -> o (the sight line).
double sightLineToBall(const Eigen::Vector3d& p, const Eigen::Vector3d& o) {
  const Eigen::Vector3d d = o - p;
  const double t = std::clamp((kBall - p).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (p + t * d - kBall).norm();
}

TEST(Projection, PatternAtVisibleVerticesNoneAtHiddenOnes) {
  const Scene scene = ballScene();
  SurfaceMapper m = mapScene(scene);
  // The imaging camera 3 cm to the side: the ball hides a patch of the
  // background that the depth cameras saw.
  const Eigen::Isometry3d T_img = lookAt({0.03, 0.01, 0}, kCentre);
  const PinholeCamera cam = testCamera();
  const FloatImage image = scene.pattern(cam, T_img, pattern);
  const ProjectionResult r = m.addImagingFrame(image, cam, T_img);
  ASSERT_EQ(r.status, SurfaceStatus::kOk);
  EXPECT_GT(r.voxels_updated, 10000u);
  EXPECT_GT(r.voxels_occluded, 1000u);
  const Mesh& mesh = m.mesh();
  const Eigen::Vector3d o = T_img.translation();
  std::size_t hidden = 0, hidden_with_value = 0, visible = 0, visible_with_value = 0;
  double sq = 0, worst = 0;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3d p = mesh.vertices[i].cast<double>();
    const bool background = std::abs(p.z() - 0.26) < 0.001;
    if (!background) continue;
    const bool has_value = std::isfinite(mesh.values[i]);
    const double sight = sightLineToBall(p, o);
    if (sight < kBallRadius - 0.002) {
      ++hidden;
      hidden_with_value += has_value;
    } else if (sight > kBallRadius + 0.002 && std::abs(p.x()) < 0.03 && std::abs(p.y()) < 0.03) {
      ++visible;
      if (!has_value) continue;
      ++visible_with_value;
      const double err = mesh.values[i] - pattern(p);
      sq += err * err;
      worst = std::max(worst, std::abs(err));
    }
  }
  const double rms = visible_with_value ? std::sqrt(sq / visible_with_value) : 0;
  std::printf("background vertices: %zu hidden (%zu with a value), %zu visible (%zu with a value), value RMS %.4f, "
              "max %.4f (pattern gradient 1 per mm)\n",
              hidden, hidden_with_value, visible, visible_with_value, rms, worst);
  ASSERT_GT(hidden, 500u);
  EXPECT_EQ(hidden_with_value, 0u);
  EXPECT_GT(visible_with_value, visible * 99 / 100);
  // The pattern changes by ~1 per mm: values within 10 um RMS of their place.
  EXPECT_LT(rms, 0.01);
  EXPECT_LT(worst, 0.05);
}

TEST(Projection, FramesAverageWithTheirWeights) {
  Scene scene;
  scene.addPlane(Eigen::Vector3d(0, 0, 1), 0.25);
  SurfaceMapper m = mapScene(scene);
  const PinholeCamera cam = testCamera();
  // Frame 1 head-on at 25 cm (weight 1 by construction: cos 1, reference distance),
  // frame 2 from 2x as far (weight 1/4): constant images 10 and 20.
  const Eigen::Isometry3d near = lookAt({0, 0, 0}, kCentre), far = lookAt({0, 0, -0.25}, kCentre);
  FloatImage a = scene.depth(cam, near), b = scene.depth(cam, far);
  std::fill(a.data.begin(), a.data.end(), 10.f);
  std::fill(b.data.begin(), b.data.end(), 20.f);
  ASSERT_EQ(m.addImagingFrame(a, cam, near).status, SurfaceStatus::kOk);
  ASSERT_EQ(m.addImagingFrame(b, cam, far).status, SurfaceStatus::kOk);
  const Mesh& mesh = m.mesh();
  std::size_t checked = 0;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3d p = mesh.vertices[i].cast<double>();
    if (p.head<2>().norm() > 0.005) continue;  // near the axis: cos ~ 1 for both
    ++checked;
    // (1 * 10 + 0.25 * 20) / 1.25 = 12
    EXPECT_NEAR(mesh.values[i], 12.0, 0.05) << "vertex " << i;
  }
  EXPECT_GT(checked, 100u);
}

TEST(Projection, DepthRenderOfThePlaneIsItsDepth) {
  Scene scene;
  scene.addPlane(Eigen::Vector3d(0, 0, 1), 0.25);
  SurfaceMapper m = mapScene(scene);
  const PinholeCamera cam = testCamera();
  const FloatImage z = renderMeshDepth(m.mesh(), cam, Eigen::Isometry3d::Identity());
  std::size_t hit = 0;
  for (float d : z.data)
    if (std::isfinite(d)) {
      ++hit;
      ASSERT_NEAR(d, 0.25, 2e-4);
    }
  EXPECT_GT(hit, 50000u);  // the 7 x 7 cm volume covers ~250 x 250 pixels
}

// RMS of (value - pattern) over the plane's vertices that have a value, and their count.
std::pair<double, std::size_t> patternError(const Mesh& mesh) {
  double sq = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (!std::isfinite(mesh.values[i])) continue;
    const Eigen::Vector3d p = mesh.vertices[i].cast<double>();
    sq += std::pow(mesh.values[i] - pattern(p), 2);
    ++n;
  }
  return {n ? std::sqrt(sq / n) : 0.0, n};
}

TEST(Projection, LensDistortionPutsThePatternInPlace) {
  Scene scene;
  scene.addPlane(Eigen::Vector3d(0, 0, 1), 0.25);
  PinholeCamera cam = testCamera();
  cam.k1 = -0.2;
  cam.k2 = 0.05;
  cam.p1 = 0.001;
  cam.p2 = -0.0005;
  // The imaging camera looks 7 cm and 5 cm beside the patch, so the patch
  // lies towards the image's corner, where the distortion is large
  // (~2 mm on the plane there).
  const Eigen::Isometry3d T_img = lookAt({0.01, 0, 0}, kCentre + Eigen::Vector3d(-0.07, -0.05, 0));
  const FloatImage image = scene.pattern(cam, T_img, pattern);
  PinholeCamera pinhole = cam;
  pinhole.k1 = pinhole.k2 = pinhole.p1 = pinhole.p2 = 0;
  SurfaceMapper with = mapScene(scene), without = mapScene(scene);
  ASSERT_EQ(with.addImagingFrame(image, cam, T_img).status, SurfaceStatus::kOk);
  ASSERT_EQ(without.addImagingFrame(image, pinhole, T_img).status, SurfaceStatus::kOk);
  const auto [rms_with, n_with] = patternError(with.mesh());
  const auto [rms_without, n_without] = patternError(without.mesh());
  std::printf("distorted camera: value RMS %.4f with the distortion (%zu vertices), %.4f without (%zu) "
              "(pattern gradient 1 per mm)\n",
              rms_with, n_with, rms_without, n_without);
  EXPECT_GT(n_with, 10000u);
  EXPECT_LT(rms_with, 0.05);    // within 50 um
  EXPECT_GT(rms_without, 0.5);  // half a millimetre and more off
}

}  // namespace
}  // namespace hapi_surface
