// Scenes and image formation of the simulation suite: the scene YAML and
// ground-truth distance, ray hits on the surfaces, the skin texture's
// contrast and corners (cv::FAST / cv::ORB at the front end's threshold),
// every trajectory keeping the scene in view, motion blur, exposure changes,
// and determinism of the rendered images.
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>
#ifdef HAPI_SIM_HAVE_FEATURES2D
#include <opencv2/features2d.hpp>
#endif
#include <cmath>

#include "hapi_sim/scenario.hpp"

using namespace hapi_sim;

namespace {

const Scene& skin() {
  static const std::unique_ptr<Scene> s = makeSkinScene();
  return *s;
}

ScenarioConfig quickConfig(TrajectoryKind kind, uint32_t seed) {
  ScenarioConfig c;
  c.scene = SceneKind::Skin;
  c.trajectory = kind;
  c.seed = seed;
  c.duration = 1.0;
  c.image_scale = 0.25;
  c.blur_samples = 4;
  return c;
}

}  // namespace

TEST(Scene, SkinYamlFollowsTheSchema) {
  EXPECT_EQ(skin().yaml(),
            "name: skin\n"
            "surfaces:\n"
            "  - {type: cylinder, centre: [0, 0, 0.045], axis: [1, 0, 0], radius: 0.045, half_length: 0.125}\n"
            "  - {type: plane, point: [0, 0, 0], normal: [0, 0, 1], half_extent: 0.6}\n");
}

TEST(Scene, DistanceToTheBoundedSurfaces) {
  const Scene& s = skin();
  EXPECT_NEAR(s.distance(Eigen::Vector3d(0.05, 0, 0.09)), 0.0, 1e-15);            // top of the arm
  EXPECT_NEAR(s.distance(Eigen::Vector3d(0.05, 0, 0.10)), 0.01, 1e-15);           // 1 cm above it
  EXPECT_NEAR(s.distance(Eigen::Vector3d(0.3, 0.2, 0.004)), 0.004, 1e-15);        // above the table
  EXPECT_NEAR(s.distance(Eigen::Vector3d(0.135, 0, 0.09)), 0.01, 1e-12);          // beyond the arm's end
  EXPECT_NEAR(s.distance(Eigen::Vector3d(0.7, 0, 0.0)), 0.1, 1e-12);              // beyond the table's rim
  SurfaceSpec sphere;
  sphere.radius = 0.2;
  EXPECT_NEAR(distanceToSurface(sphere, Eigen::Vector3d(0, 0.25, 0)), 0.05, 1e-15);
}

TEST(Scene, RayHitsLieOnTheSurfaces) {
  const Scene& s = skin();
  const StereoRigModel rig = StereoRigModel::makeDefault();
  const auto traj = makeDeviceMotion(TrajectoryKind::Handheld, s.view(), 3);
  int hits = 0;
  for (double t = 0; t < 10; t += 0.7) {
    const Pose P = traj->pose(t);
    for (int v = 0; v < 480; v += 60)
      for (int u = 0; u < 640; u += 80) {
        const Eigen::Vector3d d = P.q * pixelToRay(rig.left, Eigen::Vector2d(u, v));
        double tt;
        float g;
        if (!s.trace(P.p, d, &tt, &g)) continue;
        ++hits;
        EXPECT_LT(s.distance(P.p + tt * d), 1e-9);
        EXPECT_GT(g, 20.0f);
        EXPECT_LT(g, 240.0f);
      }
  }
  EXPECT_GT(hits, 500);
}

// The skin seen from 22 cm, blur-free, with the sensor's noise: low contrast
// (grey-level standard deviation of the skin alone under 15) yet enough
// FAST corners at threshold 20 for the front end.
TEST(Scene, SkinIsLowContrastButHasCorners) {
  const Scene& s = skin();
  const StereoRigModel rig = StereoRigModel::makeDefault();
  SceneRenderer ren(s, rig.left);
  const auto still = makeStillTrajectory(s.view(), 1);
  const Pose P = still->pose(0.0);
  const std::vector<Pose> poses(4, P);
  SensorNoise noise;
  const cv::Mat img = noise.expose(ren.radiance(poses), 1.0, 5);
  // Pixels whose ray hits the arm.
  cv::Mat mask(img.size(), CV_8UC1, cv::Scalar(0));
  for (int v = 0; v < img.rows; ++v)
    for (int u = 0; u < img.cols; ++u) {
      const Eigen::Vector3d d = P.q * pixelToRay(rig.left, Eigen::Vector2d(u, v));
      double t;
      if (intersectSurface(s.surfaces()[0], P.p, d, &t)) mask.at<uint8_t>(v, u) = 255;
    }
  ASSERT_GT(cv::countNonZero(mask), 60000);
  cv::Scalar mean, stddev;
  cv::meanStdDev(img, mean, stddev, mask);
  EXPECT_LT(stddev[0], 15.0) << "skin contrast too high";
  EXPECT_GT(stddev[0], 3.0) << "skin has no texture";
  cv::Mat inner;
  cv::erode(mask, inner, cv::Mat(), cv::Point(-1, -1), 10);  // skin only, no silhouette corners
#ifdef HAPI_SIM_HAVE_FEATURES2D
  std::vector<cv::KeyPoint> fast;
  cv::FAST(img, fast, 20, true);
  int on_skin = 0;
  for (const cv::KeyPoint& k : fast) on_skin += inner.at<uint8_t>(cvRound(k.pt.y), cvRound(k.pt.x)) ? 1 : 0;
  EXPECT_GT(on_skin, 120) << "FAST(20) corners on the skin";
  auto orb = cv::ORB::create(1000, 1.2f, 8, 31, 0, 2, cv::ORB::HARRIS_SCORE, 31, 20);
  std::vector<cv::KeyPoint> kps;
  orb->detect(img, kps, inner);
  EXPECT_GT(kps.size(), 200u) << "ORB keypoints on the skin";
  std::cerr << "skin: grey std " << stddev[0] << ", FAST(20) corners " << on_skin << ", ORB " << kps.size() << "\n";
#endif
}

// The image centre's ray hits the scene in every frame, and the arm in most
// frames (all but the loop, which visits the table on purpose, and the
// stage, meant for the patch: 30 s at 5 mm/s carries the arm's end past).
TEST(Scene, EveryTrajectoryKeepsTheSceneInView) {
  const Scene& s = skin();
  const StereoRigModel rig = StereoRigModel::makeDefault();
  for (const TrajectoryKind kind :
       {TrajectoryKind::Smooth, TrajectoryKind::Handheld, TrajectoryKind::Fast, TrajectoryKind::Loop,
        TrajectoryKind::Subject, TrajectoryKind::Measurement, TrajectoryKind::MeasurementSubject,
        TrajectoryKind::Stage}) {
    const auto device = makeDeviceMotion(kind, s.view(), 1);
    const auto scene = makeSceneMotion(kind, s.view(), 1);
    int frames = 0, on_arm = 0;
    for (double t = 0; t < 30; t += 0.05, ++frames) {
      const Pose P = relativeMotion(scene->sample(t), device->sample(t)).pose();
      const Eigen::Vector3d d = P.q * pixelToRay(rig.left, Eigen::Vector2d(rig.left.cx, rig.left.cy));
      double tt;
      float g;
      ASSERT_TRUE(s.trace(P.p, d, &tt, &g)) << trajectoryName(kind) << " t " << t;
      EXPECT_GT(tt, 0.15) << trajectoryName(kind);
      EXPECT_LT(tt, 0.45) << trajectoryName(kind);
      on_arm += intersectSurface(s.surfaces()[0], P.p, d, &tt) ? 1 : 0;
    }
    if (kind != TrajectoryKind::Loop && kind != TrajectoryKind::Stage) EXPECT_GT(on_arm, 0.8 * frames) << trajectoryName(kind);
  }
}

// A follow-up session: the arm moved 10 cm along itself and turned 20 deg
// about the vertical through its view centre, the hand's path following it.
// The camera's truth in the scene frame is the first session's, in the
// inertial frame the placement's, the IMU reads the same specific force
// (a turn about gravity), and the images are darker by the lighting gain.
TEST(Scenario, SceneOffsetAndLightingForAFollowUpSession) {
  ScenarioConfig first = quickConfig(TrajectoryKind::Handheld, 2), second = first;
  first.photometric = second.photometric = false;
  second.scene_shift = Eigen::Vector3d(0.1, 0.0, 0.0);
  second.scene_yaw = 20.0 * M_PI / 180.0;
  second.lighting_gain = 0.6;
  ASSERT_EQ(second.validate(), "");
  const Scenario a(first), b(second);
  const Eigen::Vector3d centre = b.scene().view().centre;
  const Pose placed = b.sceneInInertial(0.3).pose();
  EXPECT_LT((placed.p + placed.q * centre - centre - second.scene_shift).norm(), 1e-12);
  EXPECT_NEAR(placed.q.angularDistance(Eigen::Quaterniond::Identity()), second.scene_yaw, 1e-12);
  const Eigen::Vector3d g(0, 0, -9.81);
  for (double t = 0; t < 1.0; t += 0.1) {
    const Pose in_a = a.leftCameraInScene(t).pose(), in_b = b.leftCameraInScene(t).pose();
    EXPECT_LT((in_b.p - in_a.p).norm(), 1e-12);
    EXPECT_LT(in_b.q.angularDistance(in_a.q), 1e-12);
    const Pose expected = composePoses(placed, a.leftCameraInInertial(t).pose());
    EXPECT_LT((b.leftCameraInInertial(t).p - expected.p).norm(), 1e-12);
    const MotionSample ia = a.imuInInertial(t), ib = b.imuInInertial(t);
    EXPECT_LT((ia.q.conjugate() * (ia.a - g) - ib.q.conjugate() * (ib.a - g)).norm(), 1e-9);
    EXPECT_LT((ia.omega - ib.omega).norm(), 1e-12);
  }
  EXPECT_NEAR(b.gain(0.5) / a.gain(0.5), 0.6, 1e-12);
  cv::Mat la, ra, lb, rb;
  a.renderStereo(2, &la, &ra);
  b.renderStereo(2, &lb, &rb);
  EXPECT_NEAR(cv::mean(lb)[0] / cv::mean(la)[0], 0.6, 0.05);
  // Another skin: the same arm and light, another texture.
  ScenarioConfig other_skin = first;
  other_skin.skin_texture_seed = 7;
  cv::Mat lo, ro;
  Scenario(other_skin).renderStereo(2, &lo, &ro);
  EXPECT_NEAR(cv::mean(lo)[0] / cv::mean(la)[0], 1.0, 0.05);
  EXPECT_GT(cv::norm(lo, la, cv::NORM_L1) / la.total(), 0.3);  // grey levels per pixel (same skin: 0)
  second.lighting_gain = 0.1;
  EXPECT_NE(second.validate(), "");
  second.lighting_gain = 1.0;
  second.scene_shift = Eigen::Vector3d(2.0, 0, 0);
  EXPECT_NE(second.validate(), "");
}

TEST(ImageFormation, SameSeedSameImagesOtherSeedDiffers) {
  const Scenario a(quickConfig(TrajectoryKind::Handheld, 4)), b(quickConfig(TrajectoryKind::Handheld, 4)),
      c(quickConfig(TrajectoryKind::Handheld, 5));
  cv::Mat la, ra, lb, rb, lc, rc;
  a.renderStereo(3, &la, &ra);
  b.renderStereo(3, &lb, &rb);
  c.renderStereo(3, &lc, &rc);
  ASSERT_EQ(la.size(), cv::Size(160, 120));
  EXPECT_EQ(cv::norm(la, lb, cv::NORM_L1), 0.0);
  EXPECT_EQ(cv::norm(ra, rb, cv::NORM_L1), 0.0);
  EXPECT_GT(cv::norm(la, lc, cv::NORM_L1), 0.0);
}

// Blur over the exposure removes fine detail of a fast motion: the Laplacian
// energy drops against the same frame rendered with a zero exposure.
TEST(ImageFormation, MotionBlurFollowsTheExposure) {
  ScenarioConfig sharp = quickConfig(TrajectoryKind::Fast, 1), blurred = sharp;
  sharp.exposure = 0.0;
  blurred.exposure = 0.008;
  sharp.image_noise = blurred.image_noise = false;
  sharp.image_scale = blurred.image_scale = 0.5;
  blurred.blur_samples = sharp.blur_samples = 8;
  const Scenario A(sharp), B(blurred);
  double energy[2];
  int k = 0;
  for (const Scenario* s : {&A, &B}) {
    cv::Mat l, r, lap;
    s->renderStereo(0, &l, &r);  // t = 0: swipe and roll at their peak rates
    cv::Laplacian(l, lap, CV_32F);
    energy[k++] = cv::norm(lap, cv::NORM_L2SQR);
  }
  EXPECT_LT(energy[1], 0.8 * energy[0]);
}

TEST(ImageFormation, GainDriftsAndSteps) {
  const ExposureModel on(1, true), off(1, false);
  double lo = 10, hi = 0, max_jump = 0;
  for (double t = 0; t < 30; t += 0.01) {
    const double g = on.gain(t);
    lo = std::min(lo, g);
    hi = std::max(hi, g);
    max_jump = std::max(max_jump, std::abs(on.gain(t + 0.01) - g));
    EXPECT_EQ(off.gain(t), 1.0);
  }
  EXPECT_GT(hi - lo, 0.1);
  EXPECT_LT(lo, 1.0);
  EXPECT_GT(max_jump, 0.02);  // a step
  EXPECT_GT(lo, 0.6);
  EXPECT_LT(hi, 1.4);
}

TEST(ImageFormation, SensorNoiseHasShotAndReadNoise) {
  SensorNoise n;
  for (double level : {20.0, 160.0}) {
    const cv::Mat flat(200, 200, CV_32FC1, cv::Scalar(level));
    cv::Scalar mean, sd;
    cv::meanStdDev(n.expose(flat, 1.0, 9), mean, sd);
    const double want = std::sqrt(level / n.electrons_per_grey + n.read_noise * n.read_noise);
    EXPECT_NEAR(mean[0], level, 0.1);
    EXPECT_NEAR(sd[0], want, 0.05 * want + 0.05);  // 8-bit rounding adds 1/12 grey^2
  }
}
