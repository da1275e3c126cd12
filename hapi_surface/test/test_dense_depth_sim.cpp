// Dense depth of the simulator's skin scene (hapi_sim: forearm on a table,
// hand-held at 22 cm, lens distortion, image noise, motion blur) against the
// true depth of every rectified pixel. The figures it prints are those of
// docs/DESIGN.md "Dense depth", accuracy.
#include "hapi_surface/dense_depth.hpp"
#include "hapi_surface/dense_depth_rectifier.hpp"

#include "hapi_sim/scenario.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numeric>
#include <vector>

namespace hapi_surface {
namespace {

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * (v.size() - 1))];
}

TEST(DenseDepthSim, SkinSceneDepthUnbiased) {
  hapi_sim::ScenarioConfig cfg;
  cfg.scene = hapi_sim::SceneKind::Skin;
  cfg.trajectory = hapi_sim::TrajectoryKind::Handheld;
  cfg.duration = 2.0;
  ASSERT_EQ(cfg.validate(), "");
  const hapi_sim::Scenario sc(cfg);
  const DenseDepthSettings settings;
  const StereoRectifier rect(sc.rig().leftInfo(), sc.rig().rightInfo(), settings.image_scale);
  const DenseDepth matcher(settings);
  const RectifiedGeometry& g = rect.geometry();
  std::vector<double> err, seen;  // err: signed, estimate - truth
  for (int64_t k : {0, 7, 14}) {
    cv::Mat l_raw, r_raw, l, r;
    sc.renderStereo(k, &l_raw, &r_raw);
    rect.rectify(l_raw, r_raw, &l, &r);
    DepthImage out;
    ASSERT_EQ(matcher.compute(l, r, g, &out), "");
    // The rectified left camera is the left optical frame (R = I in the
    // simulator's CameraInfo): trace each pixel's ray into the true scene.
    const hapi_sim::Pose T = sc.leftCameraInScene(sc.frameTimeNs(k) * 1e-9).pose();
    for (int v = 0; v < g.height; v += 2)
      for (int u = 0; u < g.width; u += 2) {
        const Eigen::Vector3d ray = Eigen::Vector3d((u - g.cx) / g.fx, (v - g.cy) / g.fy, 1.0).normalized();
        double t = 0;
        float grey = 0;
        if (!sc.scene().trace(T.p, T.q * ray, &t, &grey)) continue;
        const double z_true = t * ray.z();
        if (z_true < settings.min_depth || z_true > settings.max_depth) continue;
        const float z = out.depth.at<float>(v, u);
        seen.push_back(std::isfinite(z) ? 1.0 : 0.0);
        if (std::isfinite(z)) err.push_back(z - z_true);
      }
  }
  ASSERT_GT(err.size(), 1000u);
  const double valid = std::accumulate(seen.begin(), seen.end(), 0.0) / seen.size();
  std::vector<double> abs_err(err.size());
  std::transform(err.begin(), err.end(), abs_err.begin(), [](double e) { return std::abs(e); });
  const double bias = percentile(err, 0.5), median = percentile(abs_err, 0.5), p95 = percentile(abs_err, 0.95);
  std::cout << "skin scene, 3 keyframes at image_scale " << settings.image_scale << ": valid " << 100 * valid
            << " % of the pixels in the depth range, error median " << 1e3 * bias << " mm, |error| median "
            << 1e3 * median << " mm, 95th percentile " << 1e3 * p95 << " mm\n";
  // No bias (rectification, baseline and the scaled principal point are
  // right: 0.1 px of disparity is 0.3 mm here); the noise of one keyframe,
  // which fusion averages, is about 0.4 px (DESIGN "Dense depth", accuracy).
  EXPECT_LT(std::abs(bias), 0.0003);
  EXPECT_GT(valid, 0.7);
  EXPECT_LT(median, 0.002);
  EXPECT_LT(p95, 0.008);
}

}  // namespace
}  // namespace hapi_surface
