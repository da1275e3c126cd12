// The imaging camera's perfusion pattern: its values, its YAML, and the
// rendered image against the pattern at the surface point of each pixel.
#include <gtest/gtest.h>

#include <cmath>

#include "hapi_sim/perfusion_pattern.hpp"
#include "hapi_sim/scenario.hpp"

namespace hapi_sim {
namespace {

TEST(PerfusionPattern, StepsAtTheDeclaredEdges) {
  ViewGeometry view;  // centre 0, along x, up y
  const PerfusionPattern p = PerfusionPattern::forView(view);
  const double k = 2 * M_PI / p.wave_length;
  auto smooth = [&](double s, double t) { return p.base + p.wave_amplitude * std::cos(k * s) * std::cos(k * t); };
  // Far from every band and disc: the smooth field only.
  EXPECT_NEAR(p.value(Eigen::Vector3d(0.06, 0.04, 0.0)), smooth(0.06, 0.04), 1e-9);
  // Across the first band's edge at s = -0.04: a 400 PU step within 0.2 mm.
  const double inside = p.value(Eigen::Vector3d(-0.0401, 0.04, 0)), outside = p.value(Eigen::Vector3d(-0.0399, 0.04, 0));
  EXPECT_NEAR(inside - outside, 400.0, 1.0);
  // The disc adds its value inside its radius.
  const PerfusionPattern::Disc& d = p.discs[0];
  EXPECT_NEAR(p.value(Eigen::Vector3d(d.s, d.t, 0.0)) - smooth(d.s, d.t), d.value, 1e-9);
  // The YAML names every part.
  const std::string y = p.yaml();
  for (const char* key : {"origin:", "along:", "up:", "base:", "wave_length:", "bands:", "axis: s", "axis: t", "discs:"})
    EXPECT_NE(y.find(key), std::string::npos) << key;
}

TEST(PerfusionPattern, ImagingFramesShowThePatternAtTheSurface) {
  ScenarioConfig cfg;
  cfg.scene = SceneKind::Patch;
  cfg.trajectory = TrajectoryKind::Rest;
  cfg.duration = 0.5;
  cfg.imaging_rate = 10;
  cfg.image_scale = 0.25;  // 160 x 120: quick
  cfg.imaging_content = ImagingContent::Perfusion;
  ASSERT_EQ(cfg.validate(), "");
  const Scenario sc(cfg);
  const cv::Mat img = sc.renderImaging(2);
  ASSERT_EQ(img.type(), CV_32FC1);
  const Pose T = sc.leftCameraInScene(sc.imagingTimeNs(2) * 1e-9).pose();
  const CameraModel& cam = sc.imagingCamera();
  int checked = 0;
  for (int v = 0; v < img.rows; v += 7)
    for (int u = 0; u < img.cols; u += 7) {
      const Eigen::Vector3d d = T.q * pixelToRay(cam, Eigen::Vector2d(u, v));
      double t = 0;
      float grey = 0;
      ASSERT_TRUE(sc.scene().trace(T.p, d, &t, &grey));
      EXPECT_NEAR(img.at<float>(v, u), sc.perfusionPattern().value(T.p + t * d), 1e-3);
      ++checked;
    }
  EXPECT_GT(checked, 300);
  // The default content stays the textured mono8 image.
  cfg.imaging_content = ImagingContent::Texture;
  EXPECT_EQ(Scenario(cfg).renderImaging(2).type(), CV_8UC1);
}

}  // namespace
}  // namespace hapi_sim
