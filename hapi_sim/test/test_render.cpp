#include <gtest/gtest.h>
#include <cmath>
#include "hapi_sim/globe_sim.hpp"

using namespace hapi_sim;

namespace {
GlobeScene dotScene(double lat0, double lon0) {
  GlobeScene s;
  s.radius = 0.2;
  s.centre = Eigen::Vector3d(0.05, -0.02, 0.01);
  s.texture = cv::Mat(1024, 2048, CV_32FC1, cv::Scalar(20.0f));
  // Bright Gaussian dot (sigma 3 texels, defined on the sphere surface).
  const Eigen::Vector3d n0 = (s.pointFromLatLon(lat0, lon0) - s.centre).normalized();
  const double sig = 3.0 * M_PI / 1024.0;
  for (int r = 0; r < s.texture.rows; ++r)
    for (int c = 0; c < s.texture.cols; ++c) {
      const double lat = M_PI / 2 - (r + 0.5) * M_PI / s.texture.rows;
      const double lon = -M_PI + (c + 0.5) * 2 * M_PI / s.texture.cols;
      const Eigen::Vector3d n = (s.pointFromLatLon(lat, lon) - s.centre).normalized();
      const double ang = std::acos(std::clamp(n.dot(n0), -1.0, 1.0));
      if (ang < 6 * sig) s.texture.at<float>(r, c) += 200.0f * std::exp(-0.5 * ang * ang / (sig * sig));
    }
  s.texture_source = "test-dot";
  return s;
}
}  // namespace

TEST(Render, DeterministicSameSeedDifferentSeed) {
  const GlobeScene scene = GlobeScene::makeDefault();
  const StereoRigModel rig = StereoRigModel::makeDefault();
  Trajectory traj(scene);
  Renderer ren(scene, rig.left, 2);
  const Pose P = traj.pose(3.7);
  const cv::Mat a = ren.render(P, 42, 2.0), b = ren.render(P, 42, 2.0), c = ren.render(P, 43, 2.0);
  ASSERT_EQ(a.type(), CV_8UC1);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_L1), 0.0);
  EXPECT_GT(cv::norm(a, c, cv::NORM_L1), 0.0);
  // The globe fills a good part of the image and is textured.
  cv::Scalar mean, stddev;
  cv::meanStdDev(a, mean, stddev);
  EXPECT_GT(stddev[0], 15.0);
}

TEST(Render, FallbackTextureIsDeterministic) {
  const GlobeScene s1 = GlobeScene::makeDefault("/nonexistent.jpg");
  const GlobeScene s2 = GlobeScene::makeDefault("");
  EXPECT_EQ(s1.texture_source, "generated");
  EXPECT_EQ(cv::norm(s1.texture, s2.texture, cv::NORM_L1), 0.0);
}

TEST(Render, GaussianRngMoments) {
  GaussianRng g(1);
  double m = 0, v = 0;
  const int N = 200000;
  for (int i = 0; i < N; ++i) { const double x = g.normal(); m += x; v += x * x; }
  m /= N; v = v / N - m * m;
  EXPECT_NEAR(m, 0.0, 0.01);
  EXPECT_NEAR(v, 1.0, 0.02);
  GaussianRng a(5), b(5);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(a.normal(), b.normal());
}

TEST(Geometry, DistortionRoundTrip) {
  const StereoRigModel rig = StereoRigModel::makeDefault();
  for (double x = -0.7; x <= 0.7; x += 0.1)
    for (double y = -0.5; y <= 0.5; y += 0.1) {
      const Eigen::Vector2d xn(x, y);
      const Eigen::Vector2d back = undistortNormalized(rig.left, distortNormalized(rig.left, xn));
      EXPECT_LT((back - xn).norm(), 1e-10);
    }
}

TEST(Geometry, CastRayProjectRoundTrip) {
  const GlobeScene scene = GlobeScene::makeDefault();
  const StereoRigModel rig = StereoRigModel::makeDefault();
  Trajectory traj(scene);
  int hits = 0;
  for (double t = 0; t < 20; t += 1.3) {
    const Pose P = traj.pose(t);
    for (int v = 10; v < 480; v += 37)
      for (int u = 10; u < 640; u += 41) {
        Eigen::Vector3d X;
        if (!castRay(Eigen::Vector2d(u, v), P, rig.left, scene, &X)) continue;
        ++hits;
        EXPECT_NEAR((X - scene.centre).norm(), scene.radius, 1e-9);
        Eigen::Vector2d px;
        ASSERT_TRUE(project(X, P, rig.left, &px));
        EXPECT_LT((px - Eigen::Vector2d(u, v)).norm(), 1e-6);
        Eigen::Vector3d X2;
        ASSERT_TRUE(castRay(px, P, rig.left, scene, &X2));
        EXPECT_LT((X2 - X).norm(), 1e-6);
        EXPECT_TRUE(isVisible(X, P, scene));
      }
  }
  EXPECT_GT(hits, 500);
}

TEST(Geometry, TrajectoryKeepsGlobeInView) {
  const GlobeScene scene = GlobeScene::makeDefault();
  const StereoRigModel rig = StereoRigModel::makeDefault();
  Trajectory traj(scene);
  for (double t = 0; t <= 30; t += 0.1) {
    const Pose P = traj.pose(t);
    Eigen::Vector2d px;
    ASSERT_TRUE(project(scene.centre, P, rig.left, &px));
    EXPECT_GT(px.x(), 100); EXPECT_LT(px.x(), 540);
    EXPECT_GT(px.y(), 80); EXPECT_LT(px.y(), 400);
    const double d = (P.p - scene.centre).norm();
    EXPECT_GT(d, 0.4); EXPECT_LT(d, 0.7);
  }
  // Derivatives are consistent with the pose.
  const TrajectorySample s = traj.at(5.0);
  const Pose p1 = traj.pose(5.01);
  EXPECT_LT((p1.p - (s.T_wc.p + 0.01 * s.v_w + 0.5e-4 * s.a_w)).norm(), 1e-6);
  const Eigen::Quaterniond qp = s.T_wc.q * Eigen::Quaterniond(Eigen::AngleAxisd(0.01 * s.omega_c.norm(), s.omega_c.normalized()));
  EXPECT_LT(qp.angularDistance(p1.q), 1e-4);
}

TEST(Geometry, RenderedDotLandsOnProjection) {
  // Several dots seen from several poses, both cameras.
  const StereoRigModel rig = StereoRigModel::makeDefault();
  const Eigen::Vector2d pix[] = {{200, 300}, {330, 230}, {450, 170}};
  const GlobeScene base = dotScene(0, 0);
  for (int k = 0; k < 3; ++k) {
    // Place the dot on the sphere point seen at a chosen pixel of the left camera.
    const Pose L0 = Trajectory(base).pose(2.0 + 4.0 * k);
    Eigen::Vector3d X0;
    ASSERT_TRUE(castRay(pix[k], L0, rig.left, base, &X0));
    double lat, lon;
    base.latLonFromPoint(X0, &lat, &lon);
    const GlobeScene scene = dotScene(lat, lon);
    Trajectory traj(scene);
    const Eigen::Vector3d X = scene.pointFromLatLon(lat, lon);
    for (int cam = 0; cam < 2; ++cam) {
      const Pose L = traj.pose(2.0 + 4.0 * k);
      const Pose P = cam == 0 ? L : rig.rightPose(L);
      const CameraModel& cm = cam == 0 ? rig.left : rig.right;
      ASSERT_TRUE(isVisible(X, P, scene));
      Eigen::Vector2d px;
      ASSERT_TRUE(project(X, P, cm, &px));
      Renderer ren(scene, cm, 4);
      const cv::Mat img = ren.renderFloat(P);
      double sw = 0, su = 0, sv = 0;
      const int r = 12;
      for (int v = int(px.y()) - r; v <= int(px.y()) + r; ++v)
        for (int u = int(px.x()) - r; u <= int(px.x()) + r; ++u) {
          const double w = std::max(0.0, img.at<float>(v, u) - 20.0);
          sw += w; su += w * u; sv += w * v;
        }
      ASSERT_GT(sw, 100.0);
      const Eigen::Vector2d centroid(su / sw, sv / sw);
      EXPECT_LT((centroid - px).norm(), 0.5) << "dot " << k << " cam " << cam << " proj " << px.transpose()
                                             << " centroid " << centroid.transpose();
    }
  }
}
