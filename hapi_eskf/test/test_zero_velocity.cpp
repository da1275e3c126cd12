// The zero-velocity update of a still frame (eskf/zero_velocity_update.hpp,
// eskf/still_frame_detector.hpp, docs/DESIGN.md "Zero-velocity update"):
//  * the transition, the 3-row update and the transition back equal the
//    dense Kalman update of the interval's mean velocity (correction and
//    covariance); the mean itself;
//  * a velocity the filter is sure of and that contradicts zero is gated
//    out and changes nothing; so is a pool without landmarks;
//  * the still test: bearings that keep within their re-detection noise are
//    still, a camera at HAPI's slowest hand speed is not, too few landmarks
//    give no verdict;
//  * the inertial filter: a device at rest takes the update on most frames
//    and its velocity error shrinks; a moving one never takes it.
#include "basic_settings.hpp"
#include "hapi_eskf/eskf/eskf.hpp"
#include "hapi_eskf/eskf/still_frame_detector.hpp"
#include "hapi_eskf/eskf/zero_velocity_update.hpp"
#include "inertial_scenario.hpp"
#include "test_random.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace hapi_eskf {
namespace {

// A CPU backend with an inertial pose block plus the frame error's spare
// rows, a random pose covariance and K landmarks correlated with it.
std::unique_ptr<CovarianceBackend> filledBackend(int K, testing_random::Rng& rng) {
  const int P = kInertialDim + kFrameErrorDim;
  auto backend = makeCpuBackend(10, 0, P);
  EXPECT_EQ(backend->reset(rng.spd(P, 1e-4)), Status::kOk);
  const std::vector<uint8_t> no_descriptor;
  std::vector<NewLandmarkBlock> added;
  for (int k = 0; k < K; ++k) added.push_back(testing_random::randomNewBlock(rng, no_descriptor));
  EXPECT_EQ(backend->addLandmarks(added), Status::kOk);
  return backend;
}

// Both measured combinations: the velocity alone (a model without
// acceleration) and the inertial model's interval mean, which also holds
// orientation, accelerometer bias and gravity.
TEST(ZeroVelocityUpdate, EqualsTheDenseKalmanUpdateOfTheMeanVelocity) {
  for (const bool inertial : {false, true}) {
    testing_random::Rng rng(3);
    auto backend = filledBackend(4, rng);
    const Eigen::MatrixXd C0 = backend->denseCovariance();
    const int n = static_cast<int>(C0.rows());
    const double sigma = 0.003;
    const Vec3 v_hat(0.004, -0.002, 0.001);
    const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(0.2, -0.5, 1.0).normalized()).toRotationMatrix();
    const auto J = meanVelocityJacobian(inertial, R, Vec3(0.3, -0.2, 9.7), 0.1, kInertialDim);
    ZeroVelocityUpdate zv(sigma, 1e6, backend->poseDim());
    ZeroVelocityStatus status;
    Eigen::VectorXd dx;
    ASSERT_EQ(zv.apply(backend.get(), v_hat, J, &status, &dx), Status::kOk);
    ASSERT_TRUE(status.fused);

    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(3, n);
    H.leftCols(J.cols()) = J;
    EXPECT_EQ((H.block<3, 3>(0, kIdxG).norm() > 0.0), inertial);
    const Eigen::MatrixXd S = H * C0 * H.transpose() + sigma * sigma * Eigen::MatrixXd::Identity(3, 3);
    const Eigen::MatrixXd K = C0 * H.transpose() * S.inverse();
    const Eigen::VectorXd dx_ref = K * (-v_hat);
    const Eigen::MatrixXd C_ref = C0 - K * S * K.transpose();
    ASSERT_EQ(dx.size(), n);
    EXPECT_LT((dx - dx_ref).cwiseAbs().maxCoeff(), 1e-12) << (dx - dx_ref).transpose();
    EXPECT_LT((backend->denseCovariance() - C_ref).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_NEAR(status.test_ratio * 1e6, (-v_hat).dot(S.ldlt().solve(-v_hat)), 1e-9);
    EXPECT_LT((status.innovation_variance - S.diagonal()).cwiseAbs().maxCoeff(), 1e-15);
  }
}

// The interval's mean velocity: the trapezoid rule over the steps, the
// current velocity when nothing was predicted.
TEST(ZeroVelocityUpdate, IntervalVelocityIsTheMeanOverTheSteps) {
  IntervalVelocity iv;
  EXPECT_EQ(iv.meanVelocity(Vec3(1, 2, 3)), Vec3(1, 2, 3));
  // v(t) = 0.01 sin(2 pi 17 t) over one period: mean 0, in 200 Hz steps.
  double t = 0.0;
  Vec3 v = Vec3::Zero();
  while (t < 1.0 / 17.0 - 1e-12) {
    const double t1 = std::min(t + 0.001, 1.0 / 17.0);
    const Vec3 v1(0.01 * std::sin(2 * M_PI * 17 * t1), 0.0, 0.002);
    iv.add(t, v, t1, v1);
    t = t1;
    v = v1;
  }
  EXPECT_NEAR(iv.duration(), 1.0 / 17.0, 1e-12);
  EXPECT_LT(std::abs(iv.meanVelocity(v).x()), 1e-5);
  iv.restart();
  EXPECT_EQ(iv.duration(), 0.0);
}

TEST(ZeroVelocityUpdate, AContradictedVelocityOrAnEmptyPoolChangesNothing) {
  testing_random::Rng rng(4);
  auto backend = filledBackend(3, rng);
  const Eigen::MatrixXd C0 = backend->denseCovariance();
  ZeroVelocityUpdate zv(0.003, 11.345, backend->poseDim());
  ZeroVelocityStatus status;
  Eigen::VectorXd dx;
  const auto J = meanVelocityJacobian(true, Mat3::Identity(), Vec3(0, 0, 9.81), 0.1, kInertialDim);
  // 1 m/s against a velocity sigma of about 0.01 m/s: far outside the gate.
  ASSERT_EQ(zv.apply(backend.get(), Vec3(1.0, 0.0, 0.0), J, &status, &dx), Status::kOk);
  EXPECT_TRUE(status.tested);
  EXPECT_FALSE(status.fused);
  EXPECT_GT(status.test_ratio, 1.0);
  EXPECT_EQ(backend->denseCovariance(), C0);

  auto empty = filledBackend(0, rng);
  const Eigen::MatrixXd E0 = empty->denseCovariance();
  ASSERT_EQ(zv.apply(empty.get(), Vec3::Zero(), J, &status, &dx), Status::kOk);
  EXPECT_FALSE(status.fused);
  EXPECT_EQ(empty->denseCovariance(), E0);
}

// Landmarks 0.3 m in front of the camera (HAPI's skin), re-detected with
// `noise` [m] across the ray.
std::vector<StillFrameDetector::Sighting> sightings(const Vec3& camera_shift, int n, double noise,
                                                    std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0), spread(0.0, 0.1);
  std::vector<StillFrameDetector::Sighting> out(n);
  std::mt19937 layout(99);  // the same points every frame
  for (int i = 0; i < n; ++i) {
    const Vec3 m(spread(layout), spread(layout), 0.3);
    out[i].landmark_id = 100 + i;
    out[i].z = m - camera_shift + noise * Vec3(g(rng), g(rng), 0.0);
  }
  return out;
}

// One frame: its still test, then its sightings remembered.
StillFrameVerdict onFrame(StillFrameDetector& d, double stamp, const std::vector<StillFrameDetector::Sighting>& s) {
  const StillFrameVerdict v = d.test(stamp, s);
  d.remember(stamp, s);
  return v;
}

TEST(StillFrameDetector, BearingsThatKeepStillAreStillAndAMovingCameraIsNot) {
  std::mt19937 rng(6);
  StillFrameDetector d(0.002);
  // Re-detection noise of 0.02 mm at 0.3 m (0.05 px of a 700 px lens): an
  // apparent speed of about 0.3 mm/s at 10 Hz.
  EXPECT_FALSE(onFrame(d, 0.0, sightings(Vec3::Zero(), 40, 2e-5, rng)).still);  // nothing to compare with yet
  const StillFrameVerdict still = onFrame(d, 0.1, sightings(Vec3::Zero(), 40, 2e-5, rng));
  EXPECT_EQ(still.common, 40);
  EXPECT_TRUE(still.still) << still.median_speed;
  EXPECT_LT(still.median_speed, 0.001);
  // HAPI's slowest hand motion, 6 mm/s sideways: 0.6 mm in 0.1 s.
  const StillFrameVerdict moved = onFrame(d, 0.2, sightings(Vec3(0.0006, 0.0, 0.0), 40, 2e-5, rng));
  EXPECT_FALSE(moved.still);
  EXPECT_GT(moved.median_speed, 0.004);
  // The same bearing change over a longer interval is a slower camera.
  StillFrameDetector slow(0.002);
  onFrame(slow, 0.0, sightings(Vec3::Zero(), 40, 0.0, rng));
  EXPECT_TRUE(onFrame(slow, 10.0, sightings(Vec3(0.0006, 0.0, 0.0), 40, 0.0, rng)).still);
  // Too few landmarks in common: no verdict.
  const StillFrameVerdict few = onFrame(d, 0.3, sightings(Vec3(0.0006, 0.0, 0.0), kStillMinCommonLandmarks - 1, 0.0, rng));
  EXPECT_FALSE(few.still);
  EXPECT_TRUE(std::isnan(few.median_speed));
  // A reset forgets the previous frame.
  d.reset();
  EXPECT_EQ(onFrame(d, 0.4, sightings(Vec3::Zero(), 40, 0.0, rng)).common, 0);
}

struct RestRun {
  int frames = 0, still = 0, fused = 0, fused_moving = 0;
  double velocity_rms = 0.0;  // over the frames at rest [m/s]
};

// The inertial filter on the analytic trajectory with `rest` seconds at
// rest before the motion.
RestRun runRest(double rest, double duration, bool zero_velocity_update) {
  EskfSettings s = testing_settings::inertialTrajectoryFilter();
  s.zero_velocity_update = zero_velocity_update;
  // This world's landmarks are 1.5-14 m away: the apparent speed of a
  // still camera's keypoints (re-detected within 0.02 px) is range times
  // 4e-4 /s, so the still test here takes 2 cm/s; the trajectory moves at
  // 0.14 m/s 0.2 s after its rest.
  s.still_max_speed = 0.02;
  const sim::ImuNoiseModel noise;
  std::mt19937 rng(21);
  sim::StereoRig rig;
  rig.sigma_px = 0.02;
  const sim::World world = sim::randomWorld(rng, 6000, Vec3(-20, -20, -20), Vec3(20, 20, 20));
  sim::InertialTrajectory traj;
  traj.rest = rest;
  const CameraExtrinsic e = sim::forwardCamera();
  Eskf f(s, makeCpuBackend(s.max_landmarks, 32, filterPoseDim(s)), e);
  EXPECT_EQ(f.reset(PoseState(), 0.0), Status::kOk);
  const Vec3 origin = sim::cameraOf(traj.at(0.0), e).p;
  RestRun r;
  double sum_v2 = 0.0;
  int n_rest = 0, k_imu = 1;
  for (int k = 1; k * 0.1 <= duration; ++k) {
    const double t = k * 0.1;
    for (const ImuSample& m : sim::imuSamplesUpTo(traj, noise, t, &k_imu, rng)) EXPECT_EQ(f.addImu(m), Status::kOk);
    PoseState cam = sim::cameraOf(traj.at(t), e);
    cam.p -= origin;
    IterationReport rep;
    const Status st = f.processFrame(sim::makeFrame(world, cam, rig, t, 4, rng), &rep);
    if (st == Status::kAwaitingImu) continue;
    EXPECT_EQ(st, Status::kOk) << toString(st) << " at " << t;
    ++r.frames;
    r.still += rep.zero_velocity.still.still;
    r.fused += rep.zero_velocity.fused;
    // The motion starts at `rest` with a C2 ramp: 0.2 s later it moves by
    // a few mm per frame.
    if (t > rest + 0.2) r.fused_moving += rep.zero_velocity.fused;
    if (t < rest) {
      sum_v2 += (f.state().v - traj.at(t).v).squaredNorm();
      ++n_rest;
    }
  }
  r.velocity_rms = n_rest > 0 ? std::sqrt(sum_v2 / n_rest) : 0.0;
  return r;
}

TEST(ZeroVelocityUpdate, ADeviceAtRestTakesItAndAMovingOneNever) {
  const RestRun with = runRest(4.0, 8.0, true), without = runRest(4.0, 8.0, false);
  std::printf("at rest 4 s, then moving 4 s: %d frames, %d still, %d updates fused (%d while moving); velocity "
              "RMS at rest %.5f m/s with, %.5f m/s without\n",
              with.frames, with.still, with.fused, with.fused_moving, with.velocity_rms, without.velocity_rms);
  EXPECT_GE(with.fused, 25);  // of about 36 frames at rest after the alignment
  EXPECT_EQ(with.fused_moving, 0);
  EXPECT_EQ(without.fused, 0);
  EXPECT_LT(with.velocity_rms, without.velocity_rms);
}

}  // namespace
}  // namespace hapi_eskf
