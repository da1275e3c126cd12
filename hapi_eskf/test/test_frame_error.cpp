// The frame-shared vision error (frame_error_block.hpp, docs/DESIGN.md
// "Frame-shared vision error"):
//  * open -> backend update -> close equals the joint update whose
//    measurement noise has the shared term, R + H_n Sigma_f H_n^T, in the
//    dense reference formula (covariance and correction), and leaves the
//    spare rows uncorrelated;
//  * the whole filter with a vanishing frame error equals the filter without
//    one (the spare rows change no bookkeeping);
//  * with a frame error the filter still tracks the inertial trajectory.
#include "basic_settings.hpp"
#include "hapi_eskf/eskf/eskf.hpp"
#include "hapi_eskf/eskf/frame_error_block.hpp"
#include "hapi_eskf/so3.hpp"
#include "inertial_scenario.hpp"

#include <gtest/gtest.h>

#include <random>

namespace hapi_eskf {
namespace {

Eigen::MatrixXd randomMatrix(int r, int c, std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd M(r, c);
  for (int i = 0; i < r; ++i)
    for (int j = 0; j < c; ++j) M(i, j) = g(rng);
  return M;
}

Eigen::MatrixXd randomCovariance(int n, double scale, std::mt19937& rng) {
  const Eigen::MatrixXd A = randomMatrix(n, n, rng);
  return scale * (A * A.transpose() / n + 0.1 * Eigen::MatrixXd::Identity(n, n));
}

// The filter's dense C without the spare rows (the model's layout).
Eigen::MatrixXd modelLayout(const Eigen::MatrixXd& C, int model_dim, int filter_dim) {
  const int n = static_cast<int>(C.rows()) - (filter_dim - model_dim);
  std::vector<int> keep;
  for (int i = 0; i < model_dim; ++i) keep.push_back(i);
  for (int i = filter_dim; i < C.rows(); ++i) keep.push_back(i);
  Eigen::MatrixXd out(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) out(i, j) = C(keep[i], keep[j]);
  return out;
}

TEST(FrameErrorBlock, UpdateEqualsTheJointUpdateWithTheSharedNoise) {
  std::mt19937 rng(5);
  EskfSettings s = testing_settings::basicFilter();
  s.motion_model = MotionModelKind::kGyro;  // a model with the frame error (pose block 15)
  s.frame_rotation_sigma = 0.02;
  s.frame_optical_axis_sigma = 0.03;
  s.frame_translation_sigma = 0.01;
  const int P = kGyroDim, K = 5;
  FrameErrorBlock fe(P, s);
  ASSERT_TRUE(fe.enabled());
  ASSERT_EQ(fe.filterDim(), P + kFrameErrorDim);
  ASSERT_EQ(filterPoseDim(s), P + kFrameErrorDim);
  auto backend = makeCpuBackend(10, 0, fe.filterDim());
  ASSERT_TRUE(backend);
  PoseMat C_pose = randomCovariance(P, 0.01, rng);
  ASSERT_EQ(backend->reset(fe.covariance(C_pose)), Status::kOk);
  std::vector<NewLandmarkBlock> added(K);
  for (NewLandmarkBlock& b : added) {
    b.G_pose = randomMatrix(3, 6, rng);
    b.G_z = randomMatrix(3, 3, rng);
    b.Cz = randomCovariance(3, 1e-3, rng);
  }
  ASSERT_EQ(backend->addLandmarks(added), Status::kOk);
  const Eigen::MatrixXd C0 = modelLayout(backend->denseCovariance(), P, fe.filterDim());
  const int n = static_cast<int>(C0.rows());

  // Three measurements and a camera Jacobian that is not the identity.
  Mat6 J = Mat6::Identity() + 0.3 * Mat6(randomMatrix(6, 6, rng));
  std::vector<MeasurementBlock> blocks(3);
  const int slots[3] = {0, 2, 4};
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(9, n), R = Eigen::MatrixXd::Zero(9, 9);
  Eigen::VectorXd innovation(9);
  for (int j = 0; j < 3; ++j) {
    MeasurementBlock& b = blocks[j];
    b.slot = slots[j];
    b.H_pose = randomMatrix(3, 6, rng);
    b.H_landmark = randomMatrix(3, 3, rng);
    b.R = randomCovariance(3, 1e-3, rng);
    b.innovation = 0.05 * randomMatrix(3, 1, rng);
    H.block(3 * j, 0, 3, 6) = b.H_pose;
    H.block(3 * j, landmarkRow(b.slot, P), 3, 3) = b.H_landmark;
    R.block(3 * j, 3 * j, 3, 3) = b.R;
    innovation.segment<3>(3 * j) = b.innovation;
  }
  // Reference: the shared error n (camera frame) enters every block as
  // H_pose J^-1 n, so R_joint = R + H_n Sigma_cam H_n^T.
  Mat6 sigma_cam = Mat6::Zero();
  sigma_cam.diagonal() << 1e-4, 1e-4, 1e-4, 4e-4, 4e-4, 9e-4;
  const Eigen::MatrixXd H_n = H.leftCols(6) * J.inverse();
  const Eigen::MatrixXd S = H * C0 * H.transpose() + R + H_n * sigma_cam * H_n.transpose();
  const Eigen::MatrixXd gain = C0 * H.transpose() * S.inverse();
  const Eigen::VectorXd dx_ref = gain * innovation;
  const Eigen::MatrixXd C_ref = C0 - gain * S * gain.transpose();

  ASSERT_EQ(fe.open(backend.get(), J), Status::kOk);
  EXPECT_TRUE(fe.isOpen());
  Eigen::VectorXd dx;
  ASSERT_EQ(backend->update(blocks, &dx), Status::kOk);
  const Eigen::VectorXd dpose = fe.poseCorrection(dx);
  ASSERT_EQ(fe.close(backend.get()), Status::kOk);
  EXPECT_FALSE(fe.isOpen());
  const Eigen::MatrixXd C_full = backend->denseCovariance();
  const Eigen::MatrixXd C1 = modelLayout(C_full, P, fe.filterDim());

  EXPECT_LT((C1 - C_ref).cwiseAbs().maxCoeff(), 1e-12 * C0.cwiseAbs().maxCoeff() * 1e3);
  EXPECT_LT((dpose - dx_ref.head(P)).cwiseAbs().maxCoeff(), 1e-10);
  for (int k = 0; k < K; ++k)
    EXPECT_LT((dx.segment<3>(landmarkRow(k, fe.filterDim())) - dx_ref.segment<3>(landmarkRow(k, P)))
                  .cwiseAbs()
                  .maxCoeff(),
              1e-10)
        << k;
  // The spare rows: identity, uncorrelated with the rest.
  const Eigen::MatrixXd spare_rows = C_full.middleRows(P, kFrameErrorDim);
  EXPECT_LT((spare_rows.middleCols(P, kFrameErrorDim) - Eigen::MatrixXd::Identity(6, 6)).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(spare_rows.leftCols(P).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(spare_rows.rightCols(3 * K).cwiseAbs().maxCoeff(), 0.0);
  // The shared error makes the frame's pose information smaller than with
  // independent points: the posterior pose block is larger.
  const Eigen::MatrixXd S_indep = H * C0 * H.transpose() + R;
  const Eigen::MatrixXd C_indep = C0 - C0 * H.transpose() * S_indep.inverse() * H * C0;
  EXPECT_GT(C1.topLeftCorner(6, 6).trace(), C_indep.topLeftCorner(6, 6).trace());
}

TEST(FrameErrorBlock, DisabledIsTheModelBlockAsIs) {
  const EskfSettings s = testing_settings::basicFilter();
  ASSERT_FALSE(frameErrorModelled(s));
  FrameErrorBlock fe(kInertialDim, s);
  EXPECT_EQ(fe.filterDim(), kInertialDim);
  const PoseMat F = PoseMat::Constant(kInertialDim, kInertialDim, 0.5);
  EXPECT_EQ(fe.transition(F), F);
  EXPECT_EQ(fe.noise(F), F);
  EXPECT_EQ(fe.covariance(F), F);
  auto backend = makeCpuBackend(4, 0, kInertialDim);
  EXPECT_EQ(fe.open(backend.get(), Mat6::Identity()), Status::kOk);
  EXPECT_FALSE(fe.isOpen());
}

TEST(FrameErrorBlock, ShippedForTheImuModelsOfTheEskf) {
  EskfSettings s;  // as shipped
  s.motion_model = MotionModelKind::kInertial;
  EXPECT_TRUE(frameErrorModelled(s));
  // The shipped inertial filter estimates no calibration (motion_settings.def).
  EXPECT_EQ(filterPoseDim(s), kInertialDim + kFrameErrorDim);
  s.calib_cam_timeoffset = true;
  EXPECT_EQ(filterPoseDim(s), kInertialDim + kCalibTimeOffsetDim + kFrameErrorDim);
  s.motion_model = MotionModelKind::kGyro;
  EXPECT_TRUE(frameErrorModelled(s));
  // The constant-velocity model absorbs the shared errors as motion.
  s.motion_model = MotionModelKind::kConstantVelocity;
  EXPECT_FALSE(frameErrorModelled(s));
  EXPECT_EQ(filterPoseDim(s), kCameraMotionDim);
  // The SEIF's information-form motion update inverts the transition; the
  // frame error's two transitions are singular (and neither the frame error
  // nor the calibration is modelled over it).
  s.motion_model = MotionModelKind::kInertial;
  s.backend_algorithm = BackendAlgorithm::kSeif;
  EXPECT_FALSE(frameErrorModelled(s));
  EXPECT_EQ(filterPoseDim(s), kInertialDim);
}

struct FilterRun {
  std::vector<PoseState> poses;
  std::vector<Vec3> landmarks;
  PoseMat C;
  double max_pos_err = 0, max_rot_err = 0;
};

// The inertial filter on the analytic trajectory of test_inertial.cpp.
FilterRun runInertial(double rotation_sigma, double translation_sigma, double duration) {
  EskfSettings s = testing_settings::inertialTrajectoryFilter();
  s.frame_rotation_sigma = rotation_sigma;
  s.frame_optical_axis_sigma = rotation_sigma;
  s.frame_translation_sigma = translation_sigma;
  std::mt19937 rng(11);
  const sim::StereoRig rig;
  const sim::World world = sim::randomWorld(rng, 6000, Vec3(-20, -20, -20), Vec3(20, 20, 20));
  const sim::InertialTrajectory traj;
  const sim::ImuNoiseModel noise;
  const CameraExtrinsic e = sim::forwardCamera();
  Eskf f(s, makeCpuBackend(s.max_landmarks, 32, filterPoseDim(s)), e);
  EXPECT_EQ(f.reset(PoseState(), 0.0), Status::kOk);
  const Vec3 origin = sim::cameraOf(traj.at(0.0), e).p;
  FilterRun r;
  int k_imu = 1;
  for (int k = 1; k * 0.1 <= duration; ++k) {
    const double t = k * 0.1;
    for (const ImuSample& m : sim::imuSamplesUpTo(traj, noise, t, &k_imu, rng)) EXPECT_EQ(f.addImu(m), Status::kOk);
    PoseState cam = sim::cameraOf(traj.at(t), e);
    cam.p -= origin;
    const Status st = f.processFrame(sim::makeFrame(world, cam, rig, t, 4, rng));
    if (st == Status::kAwaitingImu) continue;
    EXPECT_EQ(st, Status::kOk) << toString(st) << " at " << t;
    r.poses.push_back(f.pose());
    r.max_pos_err = std::max(r.max_pos_err, (f.pose().p - cam.p).norm());
    r.max_rot_err = std::max(r.max_rot_err, f.pose().q.angularDistance(cam.q));
  }
  r.landmarks = f.landmarkPositions();
  r.C = f.poseCovariance();
  return r;
}

TEST(FrameErrorFilter, VanishingFrameErrorEqualsNone) {
  const FilterRun none = runInertial(0.0, 0.0, 3.0), tiny = runInertial(1e-9, 1e-9, 3.0);
  ASSERT_EQ(none.poses.size(), tiny.poses.size());
  ASSERT_GT(none.poses.size(), 20u);
  for (std::size_t i = 0; i < none.poses.size(); ++i) {
    EXPECT_LT((none.poses[i].p - tiny.poses[i].p).norm(), 1e-7) << i;
    EXPECT_LT(none.poses[i].q.angularDistance(tiny.poses[i].q), 1e-7) << i;
  }
  ASSERT_EQ(none.landmarks.size(), tiny.landmarks.size());
  for (std::size_t k = 0; k < none.landmarks.size(); ++k)
    EXPECT_LT((none.landmarks[k] - tiny.landmarks[k]).norm(), 1e-7) << k;
  ASSERT_EQ(none.C.rows(), kInertialDim);
  ASSERT_EQ(tiny.C.rows(), kInertialDim);
  EXPECT_LT((none.C - tiny.C).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(FrameErrorFilter, TracksWithASharedErrorModelled) {
  const FilterRun none = runInertial(0.0, 0.0, 10.0), shared = runInertial(0.003, 0.001, 10.0);
  EXPECT_LT(shared.max_pos_err, 0.05);
  EXPECT_LT(shared.max_rot_err, 0.02);
  // Less information per frame: the pose is less certain than without.
  EXPECT_GT(shared.C.topLeftCorner(6, 6).trace(), none.C.topLeftCorner(6, 6).trace());
}

}  // namespace
}  // namespace hapi_eskf
