// The online calibration of the inertial filter (calibration_block.hpp,
// docs/DESIGN.md "Online calibration"):
//  * the camera Jacobian's calibration columns against central finite
//    differences (the time offset's against the trajectory's own motion), the
//    step's transition with the calibration rows, and the frame transition
//    T, T^-1 on a backend;
//  * a simulated hand-held run with the time offset 10 ms, the rotation 2 deg
//    and the translation 1 cm off: the estimates converge to the truth;
//  * a device at rest: the estimates and their sigma stay at the prior;
//  * with the options off the pose block is the model's 18 rows.
#include "basic_settings.hpp"
#include "hapi_eskf/eskf/calibration_block.hpp"
#include "hapi_eskf/eskf/eskf.hpp"
#include "hapi_eskf/random_draw.hpp"
#include "inertial_scenario.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace hapi_eskf {
namespace {

EskfSettings calibratingSettings() {
  EskfSettings s = testing_settings::inertialTrajectoryFilter();
  s.calib_cam_extrinsics = true;
  s.calib_cam_timeoffset = true;
  return s;
}

NominalState someState(const CameraExtrinsic& e) {
  NominalState x;
  x.p = Vec3(0.3, -0.2, 1.1);
  x.q = quatExp(Vec3(0.3, -0.5, 0.8));
  x.v = Vec3(0.4, -0.1, 0.2);
  x.b_g = Vec3(0.01, -0.02, 0.005);
  x.b_a = Vec3(0.1, 0.05, -0.08);
  x.g = Vec3(0.05, -0.02, -9.8);
  x.w = Vec3(0.7, -0.4, 1.1);
  x.f = Vec3(0.5, 9.6, -1.2);
  x.has_imu = true;
  x.R_bc = e.R_imu_cam;
  x.p_bc = e.p_imu_cam;
  x.t_d = 0.003;
  return x;
}

// The camera's error [dp, dtheta, dv, dw] between two camera views.
Eigen::Matrix<double, 12, 1> cameraError(const PoseState& c, const PoseState& c0) {
  Eigen::Matrix<double, 12, 1> e;
  e << c.p - c0.p, logSO3(c0.q.toRotationMatrix().transpose() * c.q.toRotationMatrix()), c.v - c0.v, c.w - c0.w;
  return e;
}

TEST(CalibrationModel, LayoutFollowsTheOptions) {
  EskfSettings s = calibratingSettings();
  EXPECT_EQ(poseDim(s), kInertialDim + 7);
  EXPECT_EQ(calibrationLayout(s).extrinsic, kInertialDim);
  EXPECT_EQ(calibrationLayout(s).time_offset, kInertialDim + 6);
  s.calib_cam_extrinsics = false;
  EXPECT_EQ(poseDim(s), kInertialDim + 1);
  EXPECT_EQ(calibrationLayout(s).time_offset, kInertialDim);
  s.calib_cam_timeoffset = false;
  EXPECT_EQ(poseDim(s), kInertialDim);
  EXPECT_FALSE(calibrationLayout(s).any());
  // Only the inertial model calibrates, and not over the SEIF's storage.
  s = calibratingSettings();
  s.backend_algorithm = BackendAlgorithm::kSeif;
  EXPECT_EQ(poseDim(s), kInertialDim);
  s = calibratingSettings();
  s.motion_model = MotionModelKind::kGyro;
  EXPECT_EQ(poseDim(s), kGyroDim);
  // The defaults estimate both.
  EXPECT_TRUE(EskfSettings().calib_cam_extrinsics);
  EXPECT_TRUE(EskfSettings().calib_cam_timeoffset);
}

TEST(CalibrationModel, CameraJacobianMatchesFiniteDifferences) {
  const CameraExtrinsic e = sim::forwardCamera();
  const auto m = makeMotionModel(calibratingSettings(), e);
  const CalibrationLayout l = m->calibration();
  const int P = m->poseDim();
  const NominalState x = someState(e);
  const PoseState c0 = m->camera(x);
  const Eigen::MatrixXd T = m->cameraStateJacobian(x);
  ASSERT_EQ(T.cols(), P);
  Eigen::MatrixXd Tn(12, P);
  const double h = 1e-6;
  for (int i = 0; i < P; ++i) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(P);
    d(i) = h;
    NominalState xp = x, xm = x;
    m->inject(&xp, d);
    m->inject(&xm, -d);
    Tn.col(i) = (cameraError(m->camera(xp), c0) - cameraError(m->camera(xm), c0)) / (2 * h);
  }
  // The time offset moves the camera along its motion, not camera(x).
  Tn.col(l.time_offset).setZero();
  Eigen::MatrixXd Ta = T;
  Ta.col(l.time_offset).setZero();
  EXPECT_LT((Tn - Ta).cwiseAbs().maxCoeff(), 1e-7) << "\n" << Tn - Ta;
  // The state's extrinsic places the camera.
  EXPECT_LT((c0.p - (x.p + x.q * e.p_imu_cam)).norm(), 1e-15);
  // inject and errorBetween agree on the calibration rows.
  Eigen::VectorXd d = Eigen::VectorXd::Zero(P);
  d.tail(7) << 0.01, -0.02, 0.03, 0.004, -0.005, 0.006, 0.002;
  NominalState xd = x;
  m->inject(&xd, d);
  EXPECT_LT((m->errorBetween(xd, x) - d).norm(), 1e-12);
}

// The time offset's column: the camera of the analytic trajectory a time h
// later, seen through the filter's state at t, differs by h times it.
TEST(CalibrationModel, TimeOffsetColumnIsTheCameraMotion) {
  const CameraExtrinsic e = sim::forwardCamera();
  const auto m = makeMotionModel(calibratingSettings(), e);
  const sim::InertialTrajectory traj;
  const double t = 3.0, h = 1e-5;
  const sim::BodyTruth b = traj.at(t);
  NominalState x = someState(e);
  x.p = b.p;
  x.q = b.q;
  x.v = b.v;
  x.b_g.setZero();
  x.w = b.omega;
  const Eigen::MatrixXd T = m->cameraStateJacobian(x);
  const PoseState cp = sim::cameraOf(traj.at(t + h), e), cm = sim::cameraOf(traj.at(t - h), e);
  Eigen::Matrix<double, 6, 1> dn;
  dn << (cp.p - cm.p) / (2 * h), logSO3(cm.q.toRotationMatrix().transpose() * cp.q.toRotationMatrix()) / (2 * h);
  const Eigen::Matrix<double, 6, 1> da = T.col(m->calibration().time_offset).head<6>();
  EXPECT_LT((dn - da).cwiseAbs().maxCoeff(), 1e-6) << dn.transpose() << "\n" << da.transpose();
  EXPECT_GT(da.norm(), 0.1);  // the trajectory moves at t
}

TEST(CalibrationModel, StepKeepsTheCalibration) {
  const auto m = makeMotionModel(calibratingSettings(), sim::forwardCamera());
  const NominalState x = someState(sim::forwardCamera());
  ImuSample imu;
  imu.stamp = 0.01;
  imu.gyro = Vec3(0.3, -0.2, 0.5);
  imu.accel = Vec3(0.4, 9.5, -0.9);
  NominalState y;
  PoseMat F, Q;
  m->step(x, 0.01, &imu, &y, &F, &Q);
  const int P = m->poseDim(), n = 7;
  EXPECT_TRUE(F.bottomRows(n).isApprox(PoseMat::Identity(P, P).bottomRows(n)));
  EXPECT_TRUE(F.rightCols(n).isApprox(PoseMat::Identity(P, P).rightCols(n)));
  EXPECT_EQ(Q.bottomRows(n).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(y.R_bc, x.R_bc);
  EXPECT_EQ(y.p_bc, x.p_bc);
  EXPECT_EQ(y.t_d, x.t_d);
}

// T replaces [dp, dtheta] by the camera's pose error, T^-1 restores it; the
// landmark cross-covariances follow through the backend's predict.
TEST(CalibrationBlock, TransitionGivesTheCameraErrorAndIsUndone) {
  const EskfSettings s = calibratingSettings();
  const CameraExtrinsic e = sim::forwardCamera();
  const auto m = makeMotionModel(s, e);
  const int P = m->poseDim();
  const NominalState x = someState(e);
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd A(P, P);
  for (int i = 0; i < A.size(); ++i) A.data()[i] = 0.1 * g(rng);
  const PoseMat C0 = A * A.transpose() + 0.01 * Eigen::MatrixXd::Identity(P, P);
  auto backend = makeCpuBackend(10, 0, P);
  ASSERT_EQ(backend->reset(C0), Status::kOk);
  NewLandmarkBlock nb;
  nb.G_pose.setRandom();
  nb.G_z.setIdentity();
  nb.Cz = 0.01 * Mat3::Identity();
  ASSERT_EQ(backend->addLandmarks({nb}), Status::kOk);
  const Eigen::MatrixXd D0 = backend->denseCovariance();

  const FrameErrorBlock frame_error(P, s);  // no frame error in these settings
  CalibrationBlock block(*m);
  ASSERT_TRUE(block.enabled());
  ASSERT_EQ(block.open(backend.get(), frame_error, *m, x), Status::kOk);
  EXPECT_EQ(block.cameraJacobian(*m, x), Mat6::Identity());
  const Mat12 cam = cameraCovariance(*m, x, C0);
  const PoseMat C1 = backend->poseCovariance();
  EXPECT_LT((C1.topLeftCorner<6, 6>() - cam.topLeftCorner<6, 6>()).cwiseAbs().maxCoeff(), 1e-12);
  const PoseMat T = CalibrationBlock::cameraErrorTransition(*m, x);
  EXPECT_LT((CalibrationBlock::inverseTransition(T) * T - PoseMat::Identity(P, P)).cwiseAbs().maxCoeff(), 1e-12);
  Eigen::VectorXd dx = Eigen::VectorXd::Random(P);
  EXPECT_LT((T * block.stateCorrection(dx) - dx).cwiseAbs().maxCoeff(), 1e-12);
  ASSERT_EQ(block.close(backend.get(), frame_error), Status::kOk);
  EXPECT_FALSE(block.isOpen());
  EXPECT_LT((backend->denseCovariance() - D0).cwiseAbs().maxCoeff(), 1e-12);
}

struct CalibrationRun {
  CalibrationEstimate start, end;
  Vec3 rotation_error = Vec3::Zero(), translation_error = Vec3::Zero();
  double time_offset_error = 0.0, max_pos_err = 0.0;
  int frames = 0;
};

// The filter on the analytic trajectory (200 Hz IMU, 10 Hz frames) with the
// truth's extrinsic and time offset, configured with `configured` and
// `offset_configured`. The IMU stamps its samples t_imu = t_cam + offset_true.
CalibrationRun runCalibration(const sim::InertialTrajectory& traj, const EskfSettings& s,
                              const CameraExtrinsic& configured, double duration, unsigned seed) {
  const double offset_true = 0.0;
  std::mt19937 rng(seed);
  const sim::StereoRig rig;
  const sim::World world = sim::randomWorld(rng, 6000, Vec3(-20, -20, -20), Vec3(20, 20, 20));
  const sim::ImuNoiseModel noise;
  const CameraExtrinsic truth = sim::forwardCamera();
  Eskf f(s, makeCpuBackend(s.max_landmarks, 32, filterPoseDim(s)), configured);
  EXPECT_EQ(f.reset(PoseState(), 0.0), Status::kOk);
  const Vec3 origin = sim::cameraOf(traj.at(0.0), truth).p;
  CalibrationRun r;
  const double dt_imu = 0.005;
  int k_imu = 1;
  bool started = false;
  for (int k = 1; k * 0.1 <= duration + 1e-9; ++k) {
    const double t = k * 0.1;
    for (; k_imu * dt_imu <= t + 1e-9; ++k_imu) {
      const ImuSample truth_sample = sim::imuSample(traj, noise, k_imu * dt_imu, dt_imu, rng);
      const ImuSample in =
          imuSampleOnCameraClock(truth_sample.stamp + offset_true, truth_sample.gyro, truth_sample.accel, s);
      if (in.stamp > f.time()) EXPECT_EQ(f.addImu(in), Status::kOk);
    }
    PoseState cam = sim::cameraOf(traj.at(t), truth);
    cam.p -= origin;
    const Status st = f.processFrame(sim::makeFrame(world, cam, rig, t, 4, rng));
    if (st == Status::kAwaitingImu) continue;
    EXPECT_EQ(st, Status::kOk) << toString(st) << " at " << t;
    if (std::getenv("CALIB_DEBUG") && (k % 5 == 0 || k < 8)) {
      const CalibrationEstimate c = f.calibration();
      std::printf("t %.1f rot %.5f %.5f %.5f sig %.5f %.5f %.5f | p %.4f sig %.4f | td %.5f sig %.5f | v %.4f\n", t,
                  c.rotation_change[0], c.rotation_change[1], c.rotation_change[2], c.rotation_sigma[0],
                  c.rotation_sigma[1], c.rotation_sigma[2], c.p_bc[0], c.p_bc_sigma[0], c.time_offset,
                  c.time_offset_sigma, f.state().v.norm());
      const PoseMat Cp = f.poseCovariance();
      const Mat12 Cc = f.cameraCovariance();
      std::printf("   body th sig %.5f %.5f %.5f cam th sig %.5f %.5f %.5f g sig %.4f %.4f bg sig %.5f K %d\n",
                  std::sqrt(Cp(3, 3)), std::sqrt(Cp(4, 4)), std::sqrt(Cp(5, 5)), std::sqrt(Cc(3, 3)),
                  std::sqrt(Cc(4, 4)), std::sqrt(Cc(5, 5)), std::sqrt(Cp(15, 15)), std::sqrt(Cp(16, 16)),
                  std::sqrt(Cp(9, 9)), f.numLandmarks());
      const auto lms = f.landmarks();
      if (!lms.empty()) {
        const Vec3 rel = lms[0].position - f.pose().p;
        std::printf("   lm0 dist %.2f sigma %.4f\n", rel.norm(), std::sqrt(lms[0].covariance.trace()));
      }
    }
    if (!started) r.start = f.calibration();
    started = true;
    ++r.frames;
    r.max_pos_err = std::max(r.max_pos_err, (f.pose().p - cam.p).norm());
  }
  r.end = f.calibration();
  r.rotation_error = logSO3(truth.R_imu_cam.transpose() * f.state().R_bc);
  r.translation_error = f.state().p_bc - truth.p_imu_cam;
  r.time_offset_error = f.state().t_d - offset_true;
  return r;
}

// Hand-held: turns about all three axes and translations of a few dm
// (inertial_scenario.hpp). Configured: time offset 10 ms, rotation 2 deg
// and translation 1 cm off the truth. Targets after 10 s: 0.5 ms, 0.1 deg,
// 1 mm.
TEST(CalibrationFilter, HandHeldRunFindsTheTimeOffsetAndTheExtrinsic) {
  EskfSettings s = calibratingSettings();
  s.imu_time_offset = 0.010;
  s.calib_time_offset_sigma = 0.02;
  s.calib_extrinsic_rotation_sigma = 0.05;
  s.calib_extrinsic_translation_sigma = 0.02;
  CameraExtrinsic configured = sim::forwardCamera();
  const double deg = M_PI / 180.0;
  configured.R_imu_cam = configured.R_imu_cam * expSO3(Vec3(1.2, -1.0, 1.2) * deg);  // 2 deg
  configured.p_imu_cam += Vec3(0.006, -0.006, 0.0055);                              // 1 cm
  sim::InertialTrajectory traj;
  if (std::getenv("CALIB_FAST")) {
    traj.amp_r = Vec3(0.3, 0.3, 0.3);
    traj.freq_r = Vec3(0.71, 0.53, 0.61);
    traj.amp_p = Vec3(0.15, 0.12, 0.1);
    traj.freq_p = Vec3(0.47, 0.59, 0.67);
  }
  if (std::getenv("CALIB_FEJ")) s.first_estimate_jacobians = true;
  const CalibrationRun r = runCalibration(traj, s, configured, 10.0, 5);
  std::printf("hand-held calibration after 10 s: time offset error %.3f ms (sigma %.3f), rotation error %.4f deg "
              "(sigma %.4f), translation error %.2f mm (sigma %.2f); max position error %.4f m\n",
              1e3 * r.time_offset_error, 1e3 * r.end.time_offset_sigma, r.rotation_error.norm() / deg,
              r.end.rotation_sigma.norm() / deg, 1e3 * r.translation_error.norm(), 1e3 * r.end.p_bc_sigma.norm(),
              r.max_pos_err);
  EXPECT_GT(r.frames, 90);
  EXPECT_LT(std::abs(r.time_offset_error), 0.0005);
  EXPECT_LT(r.rotation_error.norm(), 0.1 * deg);
  EXPECT_LT(r.translation_error.norm(), 0.001);
  // Consistent: each error within 3 sigma.
  EXPECT_LT(std::abs(r.time_offset_error), 3 * r.end.time_offset_sigma);
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(std::abs(r.rotation_error[i]), 3 * r.end.rotation_sigma[i]) << i;
    EXPECT_LT(std::abs(r.translation_error[i]), 3 * r.end.p_bc_sigma[i]) << i;
  }
}

// At rest nothing observes the calibration: the prior stays.
TEST(CalibrationFilter, AtRestTheEstimatesAndSigmasStayAtThePrior) {
  EskfSettings s = calibratingSettings();
  CameraExtrinsic configured = sim::forwardCamera();
  configured.R_imu_cam = configured.R_imu_cam * expSO3(Vec3(0.02, -0.01, 0.02));
  configured.p_imu_cam += Vec3(0.005, 0.0, -0.005);
  s.imu_time_offset = 0.008;
  if (std::getenv("CALIB_EXT_ONLY")) s.calib_cam_timeoffset = false;
  if (std::getenv("CALIB_OFF")) s.calib_cam_timeoffset = s.calib_cam_extrinsics = false;
  if (std::getenv("CALIB_NO_RANSAC")) s.ransac_iterations = 0;
  if (std::getenv("CALIB_FEJ")) s.first_estimate_jacobians = true;
  sim::InertialTrajectory still;
  still.amp_p.setZero();
  still.amp_r.setZero();
  const CalibrationRun r = runCalibration(still, s, configured, 8.0, 7);
  EXPECT_GT(r.frames, 70);
  EXPECT_LT(r.end.rotation_change.norm(), 1e-3);
  EXPECT_LT((r.end.p_bc - configured.p_imu_cam).norm(), 1e-3);
  EXPECT_LT(std::abs(r.end.time_offset - s.imu_time_offset), 1e-5);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(r.end.rotation_sigma[i], s.calib_extrinsic_rotation_sigma, 0.05 * s.calib_extrinsic_rotation_sigma);
    EXPECT_NEAR(r.end.p_bc_sigma[i], s.calib_extrinsic_translation_sigma,
                0.05 * s.calib_extrinsic_translation_sigma);
  }
  EXPECT_NEAR(r.end.time_offset_sigma, s.calib_time_offset_sigma, 1e-3 * s.calib_time_offset_sigma);
  std::printf("at rest: rotation change %.2e rad, sigma %.5f %.5f %.5f rad; p_bc sigma %.5f m; time offset sigma "
              "%.6f s\n",
              r.end.rotation_change.norm(), r.end.rotation_sigma[0], r.end.rotation_sigma[1],
              r.end.rotation_sigma[2], r.end.p_bc_sigma[0], r.end.time_offset_sigma);
}

TEST(CalibrationFilter, OptionsOffLeaveTheModelsPoseBlock) {
  EskfSettings s = calibratingSettings();
  s.calib_cam_extrinsics = false;
  s.calib_cam_timeoffset = false;
  Eskf f(s, makeCpuBackend(s.max_landmarks, 32, filterPoseDim(s)), sim::forwardCamera());
  ASSERT_EQ(f.reset(PoseState(), 0.0), Status::kOk);
  EXPECT_EQ(f.poseCovariance().rows(), kInertialDim);
  EXPECT_FALSE(f.calibration().extrinsic_valid);
  EXPECT_FALSE(f.calibration().time_offset_valid);
  // A sample keeps its stamp (the configured offset is the only one).
  const auto m = makeMotionModel(s, sim::forwardCamera());
  ImuSample in;
  in.stamp = 1.0;
  NominalState x;
  x.t_d = 0.5;
  EXPECT_EQ(m->onEstimatedClock(in, x).stamp, 1.0);
}

}  // namespace
}  // namespace hapi_eskf
