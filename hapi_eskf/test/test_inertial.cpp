// The inertial motion model and filter (motion_model.hpp, docs/DESIGN.md
// "Inertial prediction", "Inertial initialisation"):
//  * the step's F and the camera Jacobian against central finite differences;
//  * the step's Q against the Monte-Carlo spread of noisy propagations;
//  * the gravity alignment of a still and of a moving start;
//  * the first-estimate transition keeps the unobservable directions;
//  * the whole filter on an analytic trajectory with a biased, noisy IMU:
//    the pose follows the truth and the bias estimates end within 3 sigma,
//    also with first-estimate Jacobians.
#include "basic_settings.hpp"
#include "hapi_eskf/eskf/eskf.hpp"
#include "hapi_eskf/eskf/inertial_alignment.hpp"
#include "hapi_eskf/random_draw.hpp"
#include "inertial_scenario.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace hapi_eskf {
namespace {

EskfSettings inertialSettings() {
  EskfSettings s = testing_settings::basicFilter();
  s.motion_model = MotionModelKind::kInertial;
  return s;
}

// d errorBetween(step(x (+) d), step(x)) / d, by central differences.
Eigen::MatrixXd numericStepJacobian(const MotionModel& m, const NominalState& x, double dt, const ImuSample& imu) {
  NominalState y0;
  PoseMat F, Q;
  m.step(x, dt, &imu, &y0, &F, &Q);
  return sim::centralDifferences(m, x, m.poseDim(), [&](const NominalState& xi) -> Eigen::VectorXd {
    NominalState y;
    PoseMat Fi, Qi;
    m.step(xi, dt, &imu, &y, &Fi, &Qi);
    return m.errorBetween(y, y0);
  });
}

// A model's step transition at sim::someState() against central differences,
// for a short and a long step; the analytic F of the long step returned.
PoseMat expectStepJacobianMatches(const MotionModel& m) {
  const NominalState x = sim::someState();
  PoseMat F, Q;
  for (double dt : {0.005, 0.1}) {
    const ImuSample imu{1.0, Vec3(0.9, -0.3, 1.4), Vec3(0.8, 9.4, -0.6)};
    NominalState y;
    m.step(x, dt, &imu, &y, &F, &Q);
    const Eigen::MatrixXd Fn = numericStepJacobian(m, x, dt, imu);
    EXPECT_LT((Fn - Eigen::MatrixXd(F)).cwiseAbs().maxCoeff(), 1e-7) << "dt " << dt << "\n" << Fn - F;
  }
  return F;
}

TEST(InertialModel, StepJacobianMatchesFiniteDifferences) {
  const auto m = makeMotionModel(inertialSettings(), sim::forwardCamera());
  ASSERT_EQ(m->poseDim(), kInertialDim);
  expectStepJacobianMatches(*m);
}

// The scanned surface's motion as states (docs/DESIGN.md "Scene motion
// state"): the rows follow the calibration's, and the step's F and the
// camera Jacobian, whose twist is now relative to the surface, match
// central differences at a state where the surface moves and turns.
TEST(InertialModel, SceneMotionJacobiansMatchFiniteDifferences) {
  EskfSettings s = inertialSettings();
  s.scene_motion = true;
  EXPECT_EQ(poseDim(s), kInertialDim + kSceneMotionDim);
  EXPECT_EQ(sceneMotionLayout(s).row, kInertialDim);
  s.calib_cam_extrinsics = s.calib_cam_timeoffset = true;
  EXPECT_EQ(sceneMotionLayout(s).row, kInertialDim + kCalibExtrinsicDim + kCalibTimeOffsetDim);
  EXPECT_EQ(poseDim(s), kMaxPoseDim - kFrameErrorDim);
  const auto m = makeMotionModel(s, sim::forwardCamera());
  NominalState x = sim::someState();
  x.u_s = Vec3(0.02, -0.03, 0.01);
  x.w_s = Vec3(-0.05, 0.08, 0.12);
  for (double dt : {0.005, 0.1}) {
    const ImuSample imu{1.0, Vec3(0.9, -0.3, 1.4), Vec3(0.8, 9.4, -0.6)};
    NominalState y;
    PoseMat F, Q;
    m->step(x, dt, &imu, &y, &F, &Q);
    const Eigen::MatrixXd Fn = numericStepJacobian(*m, x, dt, imu);
    EXPECT_LT((Fn - Eigen::MatrixXd(F)).cwiseAbs().maxCoeff(), 1e-7) << "dt " << dt << "\n" << Fn - F;
  }
  const Eigen::MatrixXd T = m->cameraStateJacobian(x);
  Eigen::MatrixXd Tn = sim::numericCameraStateJacobian(*m, x);
  const int t_d = m->calibration().time_offset;
  Tn.col(t_d).setZero();  // the offset moves the camera along its motion, not camera(x)
  Eigen::MatrixXd Ta = T;
  Ta.col(t_d).setZero();
  EXPECT_LT((Tn - Ta).cwiseAbs().maxCoeff(), 1e-7) << "\n" << Tn - Ta;
  // A device moving with the surface is at rest relative to it.
  NominalState along = sim::someState();
  along.w_s = Vec3::Zero();
  along.u_s = along.v;
  along.w = along.b_g;  // no turn of its own
  EXPECT_LT(m->camera(along).v.norm(), 1e-12);
  // The surface's motion decays to its prior with the time constant.
  NominalState y;
  PoseMat F, Q;
  m->step(x, s.scene_time_constant, nullptr, &y, &F, &Q);
  EXPECT_NEAR(y.u_s.x(), x.u_s.x() * std::exp(-1.0), 1e-15);
  EXPECT_NEAR(Q(sceneMotionLayout(s).row, sceneMotionLayout(s).row),
              s.scene_velocity_sigma * s.scene_velocity_sigma * (1.0 - std::exp(-2.0)), 1e-15);
}

// The unobservable directions of the inertial state at (p, R, v, g): a
// global translation (dp = I) and a global rotation (dp = -[p]x, dtheta =
// R^T, dv = -[v]x, dg = -[g]x); docs/DESIGN.md "First-estimate Jacobians".
Eigen::Matrix<double, kInertialDim, 6> nullSpace(const NominalState& x, const Vec3& g) {
  Eigen::Matrix<double, kInertialDim, 6> N = Eigen::Matrix<double, kInertialDim, 6>::Zero();
  N.block<3, 3>(kIdxP, 0) = Mat3::Identity();
  N.block<3, 3>(kIdxP, 3) = -skew(x.p);
  N.block<3, 3>(kIdxTheta, 3) = x.q.toRotationMatrix().transpose();
  N.block<3, 3>(kIdxV, 3) = -skew(x.v);
  N.block<3, 3>(kIdxG, 3) = -skew(g);
  return N;
}

// A step that starts after an update moved the means: the transition at the
// latest means maps the null space at the predicted state (where the update
// was linearised) onto a different one than the null space at the step's
// end, which gives the filter information along unobservable directions;
// the first-estimate transition maps it exactly, and equals the usual one
// when nothing moved the means.
TEST(InertialModel, FirstEstimateTransitionKeepsTheNullSpace) {
  const auto m = makeMotionModel(inertialSettings(), sim::forwardCamera());
  const NominalState lin = sim::someState();  // predicted, before the update
  NominalState x = lin;                   // after the update
  Eigen::VectorXd dx = Eigen::VectorXd::Zero(kInertialDim);
  dx.segment<3>(kIdxP) = Vec3(0.01, -0.02, 0.015);
  dx.segment<3>(kIdxTheta) = Vec3(0.02, 0.01, -0.03);
  dx.segment<3>(kIdxV) = Vec3(-0.05, 0.03, 0.02);
  dx.segment<3>(kIdxG) = Vec3(0.02, -0.01, 0.03);
  m->inject(&x, dx);
  for (double dt : {0.005, 0.1}) {
    const ImuSample imu{1.0, Vec3(0.9, -0.3, 1.4), Vec3(0.8, 9.4, -0.6)};
    NominalState next;
    PoseMat F, Q;
    m->step(x, dt, &imu, &next, &F, &Q);
    // Gravity keeps its first estimate in the null space.
    const auto N0 = nullSpace(lin, lin.g), N1 = nullSpace(next, lin.g);
    const double usual = (F * N0 - N1).cwiseAbs().maxCoeff();
    m->firstEstimateTransition(lin, next, dt, &F);
    const double fe = (F * N0 - N1).cwiseAbs().maxCoeff();
    EXPECT_LT(fe, 1e-12) << "dt " << dt;
    EXPECT_GT(usual, 1e-4) << "dt " << dt << ": the usual transition is not what is tested";
    // Nothing moved the means: the first-estimate transition is the usual one.
    NominalState next0;
    PoseMat F0, Fe;
    m->step(lin, dt, &imu, &next0, &F0, &Q);
    Fe = F0;
    m->firstEstimateTransition(lin, next0, dt, &Fe);
    EXPECT_LT((Fe - F0).cwiseAbs().maxCoeff(), 1e-12) << "dt " << dt;
  }
}

TEST(InertialModel, CameraJacobianMatchesFiniteDifferences) {
  const auto m = makeMotionModel(inertialSettings(), sim::forwardCamera());
  const NominalState x = sim::someState();
  const Eigen::MatrixXd T = m->cameraStateJacobian(x);
  ASSERT_EQ(T.rows(), 12);
  ASSERT_EQ(T.cols(), kInertialDim);
  const Eigen::MatrixXd Tn = sim::numericCameraStateJacobian(*m, x);
  EXPECT_LT((Tn - T).cwiseAbs().maxCoeff(), 1e-7) << "\n" << Tn - T;
  // The camera pose follows the extrinsic: R_wc = R_wb R_bc, p_wc = p + R_wb p_bc.
  const CameraExtrinsic e = sim::forwardCamera();
  EXPECT_LT((m->camera(x).p - (x.p + x.q * e.p_imu_cam)).norm(), 1e-15);
  // moveCameraTo is the inverse of camera().
  NominalState x2 = x;
  m->moveCameraTo(&x2, Vec3(1, 2, 3), quatExp(Vec3(0.1, 0.2, 0.3)));
  EXPECT_LT((m->camera(x2).p - Vec3(1, 2, 3)).norm(), 1e-12);
  EXPECT_LT(m->camera(x2).q.angularDistance(quatExp(Vec3(0.1, 0.2, 0.3))), 1e-12);
}

// The propagated covariance of 40 steps with white noise and bias walks
// equals the spread of 3000 noisy propagations (sampling error of a variance
// from 3000 samples: ~2.6 %; bound 10 %).
TEST(InertialModel, ProcessNoiseMatchesMonteCarlo) {
  EskfSettings s = inertialSettings();
  s.accel_noise_density = 0.02;
  s.gyro_noise_density = 0.002;
  s.gyro_noise_inflation = 1.0;  // the sensor model alone: the Monte Carlo draws the sensor's noise
  s.accel_random_walk = 0.01;
  s.gyro_random_walk = 0.001;
  const auto m = makeMotionModel(s, CameraExtrinsic());
  const NominalState x0 = sim::someState();
  const double dt = 0.005;
  const int steps = 40, runs = 3000;
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  auto rnd = [&] { return drawVec3(g, rng); };
  // Nominal: the true samples; covariance from zero.
  std::vector<ImuSample> truth(steps);
  for (int k = 0; k < steps; ++k)
    truth[k] = ImuSample{dt * (k + 1), Vec3(0.5, -0.2, 0.9) + 0.1 * k * Vec3(0.01, 0.02, 0), Vec3(0.3, 9.7, -0.4)};
  NominalState xn = x0;
  PoseMat C = PoseMat::Zero(kInertialDim, kInertialDim);
  for (int k = 0; k < steps; ++k) {
    NominalState y;
    PoseMat F, Q;
    m->step(xn, dt, &truth[k], &y, &F, &Q);
    C = F * C * F.transpose() + Q;
    xn = y;
  }
  // Monte Carlo: the same true motion read by a noisy IMU whose biases walk;
  // the filter's state integrates the readings (its bias state held at the
  // start value), so its error is the model's error.
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(kInertialDim, kInertialDim);
  for (int r = 0; r < runs; ++r) {
    NominalState xr = x0;
    Vec3 bg = Vec3::Zero(), ba = Vec3::Zero();
    for (int k = 0; k < steps; ++k) {
      ImuSample noisy = truth[k];
      noisy.gyro += bg + s.gyro_noise_density / std::sqrt(dt) * rnd();
      noisy.accel += ba + s.accel_noise_density / std::sqrt(dt) * rnd();
      NominalState y;
      PoseMat F, Q;
      m->step(xr, dt, &noisy, &y, &F, &Q);
      xr = y;
      bg += s.gyro_random_walk * std::sqrt(dt) * rnd();
      ba += s.accel_random_walk * std::sqrt(dt) * rnd();
    }
    // The error of the nominal w.r.t. the noisy run, plus the bias error as
    // the walk put it (the state's bias is the nominal's).
    Eigen::VectorXd e = m->errorBetween(xr, xn);
    e.segment<3>(kIdxBg) = -bg;
    e.segment<3>(kIdxBa) = -ba;
    S += e * e.transpose() / runs;
  }
  for (int i = 0; i < kIdxG; ++i)
    EXPECT_NEAR(S(i, i), C(i, i), 0.1 * C(i, i)) << "state row " << i;
}

TEST(InertialAlignment, StillStartLevelsTheWorldAndTakesTheGyroBias) {
  const EskfSettings s = inertialSettings();
  const CameraExtrinsic e = sim::forwardCamera();
  const auto m = makeMotionModel(s, e);
  std::mt19937 rng(3);
  sim::InertialTrajectory traj;
  traj.rest = 10.0;  // still throughout the window
  sim::ImuNoiseModel noise;
  // A tilted body: rotate the truth about x by 0.2 rad.
  const Eigen::Quaterniond tilt(Eigen::AngleAxisd(0.2, Vec3::UnitX()));
  std::vector<ImuSample> w;
  for (int k = 1; k <= 80; ++k) {
    ImuSample m0 = sim::imuSample(traj, noise, 0.005 * k, 0.005, rng);
    m0.accel = tilt.conjugate() * (m0.accel - noise.b_a) + noise.b_a;
    w.push_back(m0);
  }
  InertialStart start;
  ASSERT_EQ(alignInertialStart(w, *m, s, &start), Status::kOk);
  EXPECT_TRUE(start.still);
  EXPECT_NEAR(start.window.accel_mean.norm(), 9.81, 0.05);
  // World z is up: the body's mean specific force maps to +z.
  Vec3 f = Vec3::Zero();
  for (const ImuSample& x : w) f += x.accel / w.size();
  EXPECT_LT((start.x.q * f.normalized() - Vec3::UnitZ()).norm(), 1e-9);
  EXPECT_LT((start.x.g - Vec3(0, 0, -9.81)).norm(), 1e-12);
  // Gyro bias: the mean rate, within 3 sigma of the truth.
  for (int i = 0; i < 3; ++i)
    EXPECT_LT(std::abs(start.x.b_g[i] - noise.b_g[i]), 3 * std::sqrt(start.C(kIdxBg + i, kIdxBg + i))) << i;
  EXPECT_NEAR(std::sqrt(start.C(kIdxV, kIdxV)), s.static_sigma_velocity, 1e-12);
  // The camera starts at the world origin.
  EXPECT_LT(m->camera(start.x).p.norm(), 1e-12);

  // Moving: no bias from the mean rate, the velocity loose.
  traj.rest = 0.0;
  w.clear();
  for (int k = 1; k <= 200; ++k) w.push_back(sim::imuSample(traj, noise, 1.0 + 0.005 * k, 0.005, rng));
  ASSERT_EQ(alignInertialStart(w, *m, s, &start), Status::kOk);
  EXPECT_FALSE(start.still);
  EXPECT_EQ(start.x.b_g, Vec3::Zero());
  EXPECT_NEAR(std::sqrt(start.C(kIdxV, kIdxV)), s.initial_sigma_velocity, 1e-12);

  // A steady turn has no spread: it is not still (its rate is no bias).
  std::vector<ImuSample> turn;
  for (int k = 1; k <= 80; ++k) turn.push_back(ImuSample{0.005 * k, Vec3(0.0, -0.2, 0.05), Vec3(0.0, -9.81, 0.0)});
  ASSERT_EQ(alignInertialStart(turn, *m, s, &start), Status::kOk);
  EXPECT_FALSE(start.still);
  EXPECT_EQ(start.x.b_g, Vec3::Zero());
  // A slower steady turn, below any bias bound, rotates gravity in the body
  // frame as a turn does (df/dt = -w x f): not still either.
  turn.clear();
  const Vec3 rate(0.0, 0.03, 0.06), f0(0.0, -9.81, 0.0);
  for (int k = 1; k <= 80; ++k) {
    const double t = 0.005 * k;
    turn.push_back(ImuSample{t, rate, expSO3(rate * t).transpose() * f0});
  }
  ASSERT_EQ(alignInertialStart(turn, *m, s, &start), Status::kOk);
  EXPECT_LT(start.window.velocity_rms, s.static_sigma_velocity);
  EXPECT_FALSE(start.still);
  // The same rate with a constant specific force is a bias: still.
  for (ImuSample& x : turn) x.accel = f0;
  ASSERT_EQ(alignInertialStart(turn, *m, s, &start), Status::kOk);
  EXPECT_TRUE(start.still);
  EXPECT_LT((start.x.b_g - rate).norm(), 1e-12);
  // Nor is a steady acceleration (|f| != g).
  for (ImuSample& x : turn) {
    x.gyro.setZero();
    x.accel = Vec3(0.0, -9.81, 3.2);  // |f| - g = 0.51 m/s^2
  }
  ASSERT_EQ(alignInertialStart(turn, *m, s, &start), Status::kOk);
  EXPECT_FALSE(start.still);

  // Free fall (no direction) and bad input are refused.
  for (ImuSample& x : w) x.accel.setZero();
  EXPECT_EQ(alignInertialStart(w, *m, s, &start), Status::kEmptyInput);
  EXPECT_EQ(alignInertialStart({w[0]}, *m, s, &start), Status::kInvalidArgument);
  w[1].gyro.x() = std::nan("");
  EXPECT_EQ(alignInertialStart(w, *m, s, &start), Status::kNonFinite);
}

// A platform at rest that vibrates (EuRoC's MAV on the ground: 0.04 rad/s
// and 0.5 m/s^2 of sample spread at 17 and 75 Hz) with a large turn-on gyro
// bias is a still start; the same samples on a hand's 1 Hz sway are not.
std::vector<ImuSample> vibratingWindow(double sway_accel, double sway_rate = 0.0) {
  const double kPi = 3.14159265358979;
  std::vector<ImuSample> w;
  for (int k = 1; k <= 60; ++k) {
    const double t = 0.005 * k;
    const double vib17 = std::sin(2 * kPi * 17 * t + 0.3), vib75 = std::sin(2 * kPi * 75 * t + 1.1);
    ImuSample m;
    m.stamp = t;
    m.gyro = Vec3(-0.002, 0.021, 0.078) + Vec3(0.05, 0.03, 0.02) * vib17 + Vec3(0.02, 0.01, 0.01) * vib75 +
             Vec3(0.0, sway_rate, 0.0) * std::sin(2 * kPi * 1.0 * t);
    m.accel = Vec3(0.0, 0.0, 9.81) + Vec3(0.5, 0.7, 0.3) * vib17 + Vec3(0.3, 0.3, 0.2) * vib75 +
              Vec3(sway_accel, 0.0, 0.0) * std::sin(2 * kPi * 1.0 * t);
    w.push_back(m);
  }
  return w;
}

TEST(InertialAlignment, AVibratingPlatformAtRestIsAStillStart) {
  const EskfSettings s = inertialSettings();
  const auto m = makeMotionModel(s, sim::forwardCamera());
  InertialStart start;
  ASSERT_EQ(alignInertialStart(vibratingWindow(0.0), *m, s, &start), Status::kOk);
  EXPECT_GT(start.window.gyro_rms, 0.08);  // the raw samples are far from quiet
  EXPECT_GT(start.window.accel_spread, 0.4);
  EXPECT_LT(start.window.velocity_rms, s.static_sigma_velocity);
  EXPECT_TRUE(start.still);
  // The bias is the mean rate, its sigma covers the vibration's residue.
  const Vec3 bias(-0.002, 0.021, 0.078);
  for (int i = 0; i < 3; ++i) {
    const double sigma = std::sqrt(start.C(kIdxBg + i, kIdxBg + i));
    EXPECT_LT(std::abs(start.x.b_g[i] - bias[i]), 3 * sigma) << i;
    EXPECT_GT(sigma, s.gyro_noise_density / std::sqrt(0.3)) << i;  // more than the datasheet's standard error
  }

  // A hand's sway (2 m/s^2 at 1 Hz) moves the velocity by centimetres per second.
  ASSERT_EQ(alignInertialStart(vibratingWindow(2.0, 0.1), *m, s, &start), Status::kOk);
  EXPECT_GT(start.window.velocity_rms, s.static_sigma_velocity);
  EXPECT_FALSE(start.still);
  EXPECT_EQ(start.x.b_g, Vec3::Zero());
}

TEST(GyroModel, StepJacobianMatchesFiniteDifferences) {
  EskfSettings s = testing_settings::basicFilter();
  s.motion_model = MotionModelKind::kGyro;
  const auto m = makeMotionModel(s, sim::forwardCamera());
  ASSERT_EQ(m->poseDim(), kGyroDim);
  const PoseMat F = expectStepJacobianMatches(*m);
  // The bias enters: a rate error of the bias's size turns the camera (0.1 s step).
  EXPECT_GT((F.block<3, 3>(kIdxTheta, kIdxGyroBias).norm()), 0.05);
}

struct InertialRun {
  double max_pos_err = 0, final_pos_err = 0, max_rot_err = 0;
  Vec3 b_g, b_a, sigma_b_g, sigma_b_a;
  int frames = 0, awaiting = 0;
};

// The filter on the analytic trajectory: 200 Hz IMU, 10 Hz stereo frames.
InertialRun runInertial(unsigned seed, double duration, const sim::ImuNoiseModel& noise,
                        bool first_estimate_jacobians = false) {
  EskfSettings s = testing_settings::inertialTrajectoryFilter();
  s.first_estimate_jacobians = first_estimate_jacobians;
  std::mt19937 rng(seed);
  const sim::StereoRig rig;
  const sim::World world = sim::randomWorld(rng, 6000, Vec3(-20, -20, -20), Vec3(20, 20, 20));
  const sim::InertialTrajectory traj;
  const CameraExtrinsic e = sim::forwardCamera();
  Eskf f(s, makeCpuBackend(s.max_landmarks, 32, poseDim(s)), e);
  EXPECT_EQ(f.reset(PoseState(), 0.0), Status::kOk);
  // The filter's world: gravity-aligned at the first camera position (the
  // truth's body starts level, so the yaw agrees).
  const Vec3 origin = sim::cameraOf(traj.at(0.0), e).p;
  InertialRun r;
  int k_imu = 1;
  for (int k = 1; k * 0.1 <= duration; ++k) {
    const double t = k * 0.1;
    for (const ImuSample& m : sim::imuSamplesUpTo(traj, noise, t, &k_imu, rng)) EXPECT_EQ(f.addImu(m), Status::kOk);
    PoseState cam = sim::cameraOf(traj.at(t), e);
    cam.p -= origin;
    const StereoFrame frame = sim::makeFrame(world, cam, rig, t, 4, rng);
    IterationReport rep;
    const Status st = f.processFrame(frame, &rep);
    if (st == Status::kAwaitingImu) {
      ++r.awaiting;
      continue;
    }
    EXPECT_EQ(st, Status::kOk) << toString(st) << " at " << t;
    EXPECT_FALSE(rep.vision_led) << "IMU and vision agree on a static scene, at " << t;
    ++r.frames;
    const PoseState est = f.pose();
    const double pe = (est.p - cam.p).norm();
    r.max_pos_err = std::max(r.max_pos_err, pe);
    r.final_pos_err = pe;
    r.max_rot_err = std::max(r.max_rot_err, est.q.angularDistance(cam.q));
  }
  const PoseMat C = f.poseCovariance();
  r.b_g = f.state().b_g;
  r.b_a = f.state().b_a;
  for (int i = 0; i < 3; ++i) {
    r.sigma_b_g[i] = std::sqrt(C(kIdxBg + i, kIdxBg + i));
    r.sigma_b_a[i] = std::sqrt(C(kIdxBa + i, kIdxBa + i));
  }
  return r;
}

TEST(InertialFilter, TracksTheTrajectoryAndTheBiasesConverge) {
  const sim::ImuNoiseModel noise;
  for (bool fej : {false, true}) {
    SCOPED_TRACE(fej ? "first-estimate Jacobians" : "Jacobians at the latest means");
    const InertialRun r = runInertial(11, 20.0, noise, fej);
    EXPECT_GE(r.awaiting, 1);  // the first frames wait for the alignment window
    EXPECT_LE(r.awaiting, 4);
    EXPECT_GT(r.frames, 190);
    EXPECT_LT(r.max_pos_err, 0.05);
    EXPECT_LT(r.max_rot_err, 0.02);
    for (int i = 0; i < 3; ++i) {
      EXPECT_LT(std::abs(r.b_g[i] - noise.b_g[i]), 3 * r.sigma_b_g[i]) << "gyro bias " << i;
      EXPECT_LT(std::abs(r.b_a[i] - noise.b_a[i]), 3 * r.sigma_b_a[i]) << "accelerometer bias " << i;
      // Converged: the uncertainty is well below the bias itself.
      EXPECT_LT(r.sigma_b_g[i], 0.5 * std::abs(noise.b_g[i])) << i;
    }
    std::printf("inertial run%s: max pos err %.4f m, max rot err %.4f rad, |b_g err| %.5f rad/s, |b_a err| %.4f m/s^2\n",
                fej ? " (first estimates)" : "", r.max_pos_err, r.max_rot_err, (r.b_g - noise.b_g).norm(),
                (r.b_a - noise.b_a).norm());
  }
}

// The device is still, the scanned scene moves (translation and rotation,
// 0.5 Hz): the IMU says "no motion", the images say "the camera moves
// relative to the surface". With the agreement check the filter reports the
// camera relative to the surface and says the scene moves; without it
// (disagreement_fraction 1) it believes the IMU and misses the motion.
struct SceneMotionRun {
  double rms_err = 0, motion_rms = 0, rms_velocity_err = 0, velocity_rms = 0;
  int frames = 0, scene_moving = 0, vision_led = 0;
};

struct MovingScene {
  double disagreement_fraction = 0.5;
  bool scene_states = false;  // docs/DESIGN.md "Scene motion state"
  // The scene's motion amplitude (1: 0.25 m and 0.05 rad, 0.39 m/s at
  // most) and the world's extent: points up to 20 m away, or a near scene
  // 0.15-0.6 m in front of the camera (HAPI's skin at 20-40 cm).
  double scale = 1.0;
  bool near = false;
};

SceneMotionRun runMovingScene(const MovingScene& m) {
  EskfSettings s = inertialSettings();
  s.max_landmarks = 300;
  s.max_new_landmarks = 30;
  s.max_update_landmarks = 60;
  s.ransac_iterations = 200;
  s.disagreement_fraction = m.disagreement_fraction;
  s.scene_motion = m.scene_states;
  s.scene_velocity_sigma = 0.8 * m.scale;
  s.scene_rate_sigma = 0.16 * m.scale;
  s.scene_time_constant = 1.0;
  std::mt19937 rng(21);
  sim::StereoRig rig;
  if (m.near) rig.min_depth = 0.1, rig.max_depth = 1.0;
  sim::InertialTrajectory still;
  still.rest = 1e9;
  const sim::ImuNoiseModel noise;
  const CameraExtrinsic e = sim::forwardCamera();
  Eskf f(s, makeCpuBackend(s.max_landmarks, 32, poseDim(s)), e);
  EXPECT_EQ(f.reset(PoseState(), 0.0), Status::kOk);
  const PoseState cam0 = sim::cameraOf(still.at(0.0), e);
  sim::World world = m.near ? sim::randomWorld(rng, 3000, Vec3(-0.3, -0.3, 0.15), Vec3(0.3, 0.3, 0.6))
                            : sim::randomWorld(rng, 6000, Vec3(-20, -20, -20), Vec3(20, 20, 20));
  if (m.near)
    for (Vec3& p : world.points) p = cam0.p + cam0.q * p;  // in front of the camera
  // The scene (its frame = the filter's world at start) moves after 2 s:
  // T_world_scene(t); the camera in the scene frame, relative to its start,
  // is its inverse applied to the still camera.
  auto cameraInScene = [&](double t) {
    const double a = t > 2.0 ? m.scale * std::sin(M_PI * (t - 2.0)) : 0.0;
    const Eigen::Quaterniond q_ws = quatExp(Vec3(0.0, 0.0, 0.05 * a));
    const Vec3 p_ws(0.0, 0.25 * a, 0.1 * a);
    PoseState cam;
    cam.q = q_ws.conjugate() * cam0.q;
    cam.p = q_ws.conjugate() * (cam0.p - p_ws) - cam0.p;
    return cam;
  };
  SceneMotionRun r;
  int k_imu = 1;
  for (int k = 1; k <= 100; ++k) {
    const double t = k * 0.1;
    for (; k_imu * 0.005 <= t + 1e-9; ++k_imu)
      EXPECT_EQ(f.addImu(sim::imuSample(still, noise, k_imu * 0.005, 0.005, rng)), Status::kOk);
    const PoseState cam = cameraInScene(t);
    PoseState cam_scene = cam;
    cam_scene.p += cam0.p;
    // Landmarks are fixed in the scene frame: measure them from the camera's
    // pose in that frame (the world of randomWorld is the scene frame).
    const StereoFrame frame = sim::makeFrame(world, cam_scene, rig, t, 4, rng);
    IterationReport rep;
    const Status st = f.processFrame(frame, &rep);
    if (st == Status::kAwaitingImu) continue;
    EXPECT_EQ(st, Status::kOk) << toString(st) << " at " << t;
    if (t <= 2.0) continue;
    ++r.frames;
    r.scene_moving += rep.scene_moving;
    r.vision_led += rep.vision_led;
    r.rms_err += (f.pose().p - cam.p).squaredNorm();
    r.motion_rms += cam.p.squaredNorm();
    // The camera's velocity relative to the scene, in the scene frame.
    const Vec3 v_true = (cameraInScene(t + 1e-4).p - cameraInScene(t - 1e-4).p) / 2e-4;
    r.rms_velocity_err += (f.pose().q * f.pose().v - v_true).squaredNorm();
    r.velocity_rms += v_true.squaredNorm();
  }
  for (double* x : {&r.rms_err, &r.motion_rms, &r.rms_velocity_err, &r.velocity_rms}) *x = std::sqrt(*x / r.frames);
  return r;
}

TEST(InertialFilter, FollowsTheSurfaceWhenTheSceneMovesAndTheDeviceIsStill) {
  MovingScene check, none;
  none.disagreement_fraction = 1.0;
  const SceneMotionRun on = runMovingScene(check), off = runMovingScene(none);
  std::printf("moving scene: camera motion rms %.3f m; error with the check %.4f m (%d/%d frames scene moving), "
              "without %.4f m\n",
              on.motion_rms, on.rms_err, on.scene_moving, on.frames, off.rms_err);
  EXPECT_GT(on.motion_rms, 0.1);
  EXPECT_LT(on.rms_err, 0.1 * on.motion_rms);
  EXPECT_GT(on.scene_moving, on.frames / 2);
  EXPECT_EQ(off.vision_led, 0);
  EXPECT_GT(off.rms_err, 2.0 * on.rms_err);
}

// A near scene (15-60 cm away) moving at up to 8 cm/s under the held
// device, with the surface's motion as states (docs/DESIGN.md "Scene motion
// state"): the filter tracks the camera relative to the surface through its
// own prediction, without vision-led frames, and its relative velocity is
// better than the vision-led frames' displacement over the interval.
TEST(InertialFilter, SceneMotionStatesTrackTheSurfaceWithoutVisionLeading) {
  MovingScene states, led;
  states.scene_states = true;
  states.near = led.near = true;
  states.scale = led.scale = 0.1;
  const SceneMotionRun a = runMovingScene(states), b = runMovingScene(led);
  std::printf("near moving scene: motion %.4f m, %.4f m/s rms; scene states: error %.4f m, %.4f m/s (%d vision-led "
              "of %d frames); vision-led: %.4f m, %.4f m/s (%d)\n",
              a.motion_rms, a.velocity_rms, a.rms_err, a.rms_velocity_err, a.vision_led, a.frames, b.rms_err,
              b.rms_velocity_err, b.vision_led);
  EXPECT_LT(a.rms_err, 0.1 * a.motion_rms);
  EXPECT_LT(a.vision_led, a.frames / 10);
  EXPECT_GT(b.vision_led, b.frames / 2);
  EXPECT_LT(a.rms_velocity_err, 0.2 * a.velocity_rms);
  EXPECT_LT(a.rms_velocity_err, b.rms_velocity_err);
}

// The chained prediction (Eskf::predictStepTo) applied to C once equals the
// single steps applied one by one: C <- F C F^T + Q on the pose rows and
// columns, for every sample.
// An inertial filter over a random world of 3000 points (the inertial
// trajectory, forward camera, 200 Hz IMU), fed samples until its gravity
// alignment is done; k: the next sample's index.
struct AlignedFilter {
  AlignedFilter(const EskfSettings& s, unsigned seed)
      : rng(seed), world(sim::randomWorld(rng, 3000, Vec3(-20, -20, -20), Vec3(20, 20, 20))),
        e(sim::forwardCamera()), f(s, makeCpuBackend(s.max_landmarks, 32, poseDim(s)), e) {
    EXPECT_EQ(f.reset(PoseState(), 0.0), Status::kOk);
    for (; f.awaitingAlignment(); ++k) EXPECT_EQ(f.addImu(nextSample()), Status::kOk);
  }
  ImuSample nextSample() { return sim::imuSample(traj, noise, 0.005 * k, 0.005, rng); }
  std::mt19937 rng;
  const sim::StereoRig rig;
  const sim::World world;
  const sim::InertialTrajectory traj;
  const sim::ImuNoiseModel noise;
  const CameraExtrinsic e;
  Eskf f;
  int k = 1;
};

TEST(InertialFilter, ChainedPredictionEqualsStepByStep) {
  EskfSettings s = inertialSettings();
  s.max_landmarks = 300;
  s.max_new_landmarks = 50;
  AlignedFilter a(s, 4);
  auto& [rng, rig, world, traj, noise, e, f, k] = a;
  PoseState cam = sim::cameraOf(traj.at(f.time()), e);
  cam.p -= sim::cameraOf(traj.at(0.0), e).p;
  ASSERT_EQ(f.processFrame(sim::makeFrame(world, cam, rig, f.time(), 0, rng)), Status::kOk);
  ASSERT_GT(f.numLandmarks(), 10);
  Eigen::MatrixXd C = f.backend().denseCovariance();
  NominalState x = f.state();
  const auto m = makeMotionModel(s, e);
  const int P = kInertialDim, n = static_cast<int>(C.rows());
  for (int i = 0; i < 20; ++i, ++k) {
    const ImuSample smp = sim::imuSample(traj, noise, 0.005 * k, 0.005, rng);
    NominalState y;
    PoseMat F, Q;
    m->step(x, smp.stamp - (i == 0 ? f.time() : 0.005 * (k - 1)), &smp, &y, &F, &Q);
    x = y;
    Eigen::MatrixXd Fn = Eigen::MatrixXd::Identity(n, n);
    Fn.topLeftCorner(P, P) = F;
    C = Fn * C * Fn.transpose();
    C.topLeftCorner(P, P) += Q;
    ASSERT_EQ(f.addImu(smp), Status::kOk);
  }
  EXPECT_LT((f.poseCovariance() - C.topLeftCorner(P, P)).cwiseAbs().maxCoeff(), 1e-12 * C.cwiseAbs().maxCoeff());
  ASSERT_EQ(f.predictTo(f.time()), Status::kOk);  // a no-op step: flushes the chained steps into the backend
  const Eigen::MatrixXd D = f.backend().denseCovariance();
  EXPECT_LT((D - C).cwiseAbs().maxCoeff(), 1e-12 * C.cwiseAbs().maxCoeff());
  EXPECT_GT(C.bottomLeftCorner(n - P, P).norm(), 0.0);  // the cross block took part
}

// The world is the first camera's (docs/DESIGN.md "Inertial
// initialisation"): the alignment completes with its window's last sample,
// the first frame comes 0.1 s later and aligns again over the window grown
// to its stamp. Its camera then has the initial pose sigmas, not the
// moving start's velocity and gyro-bias uncertainty predicted over the gap
// (0.2 m/s and 0.1 rad/s for 0.1 s: 2 cm and 0.6 deg), and so do the
// landmarks it starts.
TEST(InertialFilter, TheFirstFrameAlignsAgainSoTheWorldIsItsCamera) {
  EskfSettings s = inertialSettings();
  s.static_sigma_velocity = 1e-6;  // a moving start (the trajectory accelerates smoothly)
  AlignedFilter a(s, 6);
  auto& [rng, rig, world, traj, noise, e, f, k] = a;
  const double t_aligned = f.time(), t_frame = 0.005 * (k + 19);
  for (; 0.005 * k <= t_frame + 1e-9; ++k)
    ASSERT_EQ(f.addImu(sim::imuSample(traj, noise, 0.005 * k, 0.005, rng)), Status::kOk);
  const double sigma_p_before = std::sqrt(f.cameraCovariance().block<3, 3>(0, 0).trace() / 3.0);
  const PoseState cam = sim::cameraOf(traj.at(t_frame), e);
  ASSERT_EQ(f.processFrame(sim::makeFrame(world, cam, rig, t_frame, 0, rng)), Status::kOk);
  const Mat12 C = f.cameraCovariance();
  const double sigma_p = std::sqrt(C.block<3, 3>(0, 0).trace() / 3.0), sigma_r = std::sqrt(C.block<3, 3>(3, 3).trace() / 3.0);
  std::printf("aligned at %.3f s, first frame at %.3f s: camera 1 sigma %.2f mm / %.3f deg (%.1f mm predicted over the gap)\n",
              t_aligned, t_frame, 1e3 * sigma_p, sigma_r * 180.0 / M_PI, 1e3 * sigma_p_before);
  EXPECT_NEAR(t_frame - t_aligned, 0.1, 1e-9);
  EXPECT_GT(sigma_p_before, 0.01);
  EXPECT_LT(sigma_p, 2.0 * s.initial_sigma_position);
  EXPECT_LT(sigma_r, 2.0 * s.initial_sigma_orientation);
  EXPECT_EQ(f.time(), t_frame);
  EXPECT_LT(f.frameCamera().p.norm(), 1e-9);  // the origin is this camera
  // And the filter goes on from there.
  const double t_next = t_frame + 0.1;
  for (; 0.005 * k <= t_next + 1e-9; ++k) ASSERT_EQ(f.addImu(sim::imuSample(traj, noise, 0.005 * k, 0.005, rng)), Status::kOk);
  const PoseState cam2 = sim::cameraOf(traj.at(t_next), e);
  ASSERT_EQ(f.processFrame(sim::makeFrame(world, cam2, rig, t_next, 1, rng)), Status::kOk);
  EXPECT_EQ(f.time(), t_next);
}

// Bad IMU input never changes the state: non-finite samples, samples before
// the filter time, and IMU samples to a model without IMU.
TEST(InertialFilter, BadImuInputLeavesTheStateUnchanged) {
  const EskfSettings s = inertialSettings();
  Eskf f(s, makeCpuBackend(s.max_landmarks, 32, kInertialDim), sim::forwardCamera());
  ASSERT_EQ(f.reset(PoseState(), 0.0), Status::kOk);
  EXPECT_TRUE(f.awaitingAlignment());
  StereoFrame fr;
  fr.stamp = 0.05;
  EXPECT_EQ(f.processFrame(fr), Status::kAwaitingImu);
  EXPECT_EQ(f.predictTo(0.05), Status::kAwaitingImu);
  std::mt19937 rng(1);
  const sim::InertialTrajectory traj;
  const sim::ImuNoiseModel noise;
  double t = 0.0;
  while (f.awaitingAlignment()) {
    t += 0.005;
    ASSERT_EQ(f.addImu(sim::imuSample(traj, noise, t, 0.005, rng)), Status::kOk);
  }
  const NominalState x = f.state();
  const PoseMat C = f.poseCovariance();
  const double nan = std::nan("");
  EXPECT_EQ(f.addImu(ImuSample{t + 0.005, Vec3(nan, 0, 0), Vec3(0, 0, 9.81)}), Status::kNonFinite);
  EXPECT_EQ(f.addImu(ImuSample{t + 0.005, Vec3::Zero(), Vec3(0, nan, 9.81)}), Status::kNonFinite);
  EXPECT_EQ(f.addImu(ImuSample{nan, Vec3::Zero(), Vec3(0, 0, 9.81)}), Status::kNonFinite);
  EXPECT_EQ(f.addImu(ImuSample{t - 0.001, Vec3::Zero(), Vec3(0, 0, 9.81)}), Status::kInvalidArgument);
  EXPECT_EQ(f.time(), t);
  EXPECT_EQ(f.state().p, x.p);
  EXPECT_EQ(f.state().v, x.v);
  EXPECT_EQ(f.state().b_g, x.b_g);
  EXPECT_EQ((f.poseCovariance() - C).norm(), 0.0);
  // A bad extrinsic is refused too.
  CameraExtrinsic bad;
  bad.R_imu_cam = 2.0 * Mat3::Identity();
  EXPECT_EQ(f.setCameraExtrinsic(bad), Status::kInvalidArgument);
  bad.p_imu_cam.x() = nan;
  EXPECT_EQ(f.setCameraExtrinsic(bad), Status::kNonFinite);
}

}  // namespace
}  // namespace hapi_eskf
