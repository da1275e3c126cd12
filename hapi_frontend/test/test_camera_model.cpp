// Keypoint undistortion round trip (plumb_bob, rational_polynomial), calibration
// validation, rig extrinsics and the fundamental matrix.
#include "hapi_frontend/camera_model.hpp"

#include <gtest/gtest.h>
#include <Eigen/Dense>

using namespace hapi_frontend;

namespace {
CameraCalib makeCalib(const std::string& model, const std::vector<double>& D) {
  CameraCalib c;
  c.width = 640;
  c.height = 480;
  c.distortion_model = model;
  c.D = D;
  c.K = {502.3, 0, 321.4, 0, 501.8, 238.7, 0, 0, 1};
  c.P = {502.3, 0, 321.4, 0, 0, 501.8, 238.7, 0, 0, 0, 1, 0};
  return c;
}

// distort() then undistort() over the whole image must return the input.
void roundTrip(const CameraCalib& c, double tol_px) {
  ASSERT_EQ(c.validate(), "");
  CameraModel cam(c, false);
  std::vector<cv::Point2f> dist;
  std::vector<Eigen::Vector2d> und_in;
  for (double v = 0; v <= 479; v += 40)
    for (double u = 0; u <= 639; u += 40) {
      const Eigen::Vector2d d = cam.distort({u, v});
      und_in.push_back({u, v});
      dist.emplace_back(static_cast<float>(d.x()), static_cast<float>(d.y()));
    }
  const auto und = cam.undistort(dist);
  double worst = 0, moved = 0;
  for (size_t i = 0; i < und.size(); ++i) {
    worst = std::max(worst, (und[i] - und_in[i]).norm());
    moved = std::max(moved, (Eigen::Vector2d(dist[i].x, dist[i].y) - und_in[i]).norm());
  }
  EXPECT_LT(worst, tol_px);
  EXPECT_GT(moved, 2.0) << "distortion too weak for a meaningful round trip";
}
}  // namespace

TEST(CameraModel, PlumbBobRoundTrip) {
  roundTrip(makeCalib("plumb_bob", {-0.28, 0.07, 2e-4, -1.5e-4, 0.0}), 2e-3);  // float input ~1e-4 px
}

TEST(CameraModel, RationalPolynomialRoundTrip) {
  roundTrip(makeCalib("rational_polynomial", {0.4, -0.1, 1e-4, -2e-4, 0.01, 0.7, -0.05, 0.02}), 2e-3);
}

TEST(CameraModel, NoDistortionIsIdentityAndRectifiedUsesP) {
  CameraCalib c = makeCalib("plumb_bob", {});
  CameraModel cam(c, false);
  const auto u = cam.undistort({{10.5f, 20.25f}});
  EXPECT_DOUBLE_EQ(u[0].x(), 10.5);
  EXPECT_DOUBLE_EQ(u[0].y(), 20.25);
  c.D = {-0.3, 0.1, 0, 0, 0};
  c.P[0] = 400;
  CameraModel rect(c, true);
  EXPECT_DOUBLE_EQ(rect.K()(0, 0), 400.0);
  EXPECT_DOUBLE_EQ(rect.undistort({{100.f, 50.f}})[0].x(), 100.0);
}

TEST(CameraModel, ValidateRejectsBadCalibrations) {
  EXPECT_EQ(makeCalib("plumb_bob", {0, 0, 0, 0, 0}).validate(), "");
  CameraCalib c = makeCalib("plumb_bob", {0, 0, 0, 0, 0});
  c.K[0] = 0;
  EXPECT_NE(c.validate(), "");
  c = makeCalib("plumb_bob", {0, 0, 0, 0, 0});
  c.width = 0;
  EXPECT_NE(c.validate(), "");
  EXPECT_NE(makeCalib("equidistant", {0, 0, 0, 0}).validate(), "");
  EXPECT_NE(makeCalib("plumb_bob", {0, 0, 0}).validate(), "");
  EXPECT_NE(makeCalib("rational_polynomial", {0, 0, 0, 0, 0}).validate(), "");
  EXPECT_NE(makeCalib("plumb_bob", {NAN, 0, 0, 0, 0}).validate(), "");
}

TEST(StereoRig, ExtrinsicsAndEpipolarConstraint) {
  // Rectifying rotations of a slightly converged rig.
  const Eigen::Matrix3d Rl = Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Matrix3d Rr = Eigen::AngleAxisd(-0.03, Eigen::Vector3d::UnitY()).toRotationMatrix() *
                             Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitX()).toRotationMatrix();
  CameraCalib l = makeCalib("plumb_bob", {}), r = makeCalib("plumb_bob", {});
  for (int i = 0; i < 9; ++i) {
    l.R[i] = Rl(i / 3, i % 3);
    r.R[i] = Rr(i / 3, i % 3);
  }
  r.P[3] = -502.3 * 0.12;
  const StereoRig rig = StereoRig::fromCalib(l, r, false);
  EXPECT_NEAR(rig.t_lr.norm(), 0.12, 1e-12);
  // The right camera centre, seen in the rectified frame, is +B along x.
  EXPECT_TRUE((Rl * rig.t_lr).isApprox(Eigen::Vector3d(0.12, 0, 0), 1e-12));
  Eigen::Matrix3d K;
  K << 502.3, 0, 321.4, 0, 501.8, 238.7, 0, 0, 1;
  const Eigen::Matrix3d F = rig.fundamental(K, K);
  for (int k = 0; k < 20; ++k) {
    const Eigen::Vector3d X(-0.5 + 0.05 * k, 0.3 - 0.03 * k, 1.0 + 0.2 * k);  // left frame
    const Eigen::Vector3d xl = K * X;
    const Eigen::Vector3d xr = K * (rig.R_lr.transpose() * (X - rig.t_lr));
    const Eigen::Vector3d pl = xl / xl.z(), pr = xr / xr.z();
    const Eigen::Vector3d line = F * pl;
    EXPECT_LT(std::abs(pr.dot(line)) / line.head<2>().norm(), 1e-9);  // [px]
    // A point 3 px off the true right pixel is 3 px off the line in y for this rig (almost horizontal lines).
    EXPECT_GT(std::abs((pr + Eigen::Vector3d(0, 3, 0)).dot(line)) / line.head<2>().norm(), 2.5);
  }
}
