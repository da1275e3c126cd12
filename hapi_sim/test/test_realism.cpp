// The "real" realism profile (realism.hpp): turn-on biases within their
// bounds and drawn from the seed; the vibration's spectral lines and in-situ
// standard deviation (EuRoC's measured standstill); scale factor and
// misalignment applied to the readings; the calibration the filter is told
// off by the configured amounts while the truth stays exact; the real lens
// in the rig and CameraInfo, its projection equal to OpenCV's; the option.
#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include <cmath>
#include <complex>
#include <stdexcept>
#include <vector>

#include "hapi_sim/imu_model.hpp"
#include "hapi_sim/realism.hpp"
#include "hapi_sim/scenario.hpp"
#include "hapi_sim/scenario_options.hpp"

using namespace hapi_sim;

namespace {

constexpr double kRate = 200.0;
const double kDeg = M_PI / 180.0;

MotionSample rest() { return StaticMotion().sample(0.0); }

// Amplitude of the line at f Hz of a real series sampled at kRate (single-bin DFT).
double lineAmplitude(const std::vector<double>& x, double f) {
  std::complex<double> s = 0;
  for (size_t n = 0; n < x.size(); ++n) s += x[n] * std::polar(1.0, -2.0 * M_PI * f * n / kRate);
  return 2.0 * std::abs(s) / static_cast<double>(x.size());
}

double stddev(const std::vector<double>& x) {
  double m = 0, v = 0;
  for (double a : x) m += a;
  m /= x.size();
  for (double a : x) v += (a - m) * (a - m);
  return std::sqrt(v / x.size());
}

ScenarioConfig smallConfig(Realism realism, uint32_t seed = 1) {
  ScenarioConfig c;
  c.realism = realism;
  c.seed = seed;
  c.duration = 1.0;
  c.image_scale = 0.1;
  return c;
}

double angleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return Eigen::AngleAxisd(a.conjugate() * b).angle();
}

}  // namespace

TEST(Realism, TurnOnBiasIsWithinItsBoundsAndDrawnFromTheSeed) {
  const RealismProfile real = RealismProfile::real();
  double gmax = 0, amax = 0;
  for (uint32_t seed = 1; seed <= 40; ++seed) {
    ImuModel m(ImuSpec::adis16448(), kRate, seed, true, false, real.imu);
    const ImuReading r = m.measure(rest());
    gmax = std::max(gmax, r.gyro_bias.cwiseAbs().maxCoeff());
    amax = std::max(amax, r.accel_bias.cwiseAbs().maxCoeff());
    ImuModel again(ImuSpec::adis16448(), kRate, seed, true, false, real.imu);
    EXPECT_EQ(again.measure(rest()).gyro_bias, r.gyro_bias) << "seed " << seed;
  }
  EXPECT_LE(gmax, real.imu.gyro_turn_on_bound);
  EXPECT_LE(amax, real.imu.accel_turn_on_bound);
  // Spread over the bound, not the ideal profile's 0.0035 rad/s sigma.
  EXPECT_GT(gmax, 0.8 * real.imu.gyro_turn_on_bound);
  EXPECT_GT(amax, 0.8 * real.imu.accel_turn_on_bound);
  ImuModel a(ImuSpec::adis16448(), kRate, 5, true, false, real.imu), b(ImuSpec::adis16448(), kRate, 6, true, false, real.imu);
  EXPECT_NE(a.measure(rest()).gyro_bias, b.measure(rest()).gyro_bias);
}

// At rest the in-situ standard deviation is the EuRoC standstill's (plus the
// datasheet white noise), with lines at 17 and 75 Hz and none between.
TEST(Realism, VibrationHasTheMeasuredLinesAndStandardDeviation) {
  const RealismProfile real = RealismProfile::real();
  const ImuSpec spec = ImuSpec::adis16448();
  ImuModel m(spec, kRate, 3, true, false, real.imu);
  const MotionSample still = rest();
  const Eigen::Vector3d f = m.accelMatrix() * ImuModel::specificForce(still);
  const int N = 60 * static_cast<int>(kRate);
  std::vector<double> g[3], a[3];
  for (int n = 0; n < N; ++n) {
    const ImuReading r = m.measure(still);
    for (int i = 0; i < 3; ++i) {
      g[i].push_back(r.gyro[i] - r.gyro_bias[i]);
      a[i].push_back(r.accel[i] - f[i] - r.accel_bias[i]);
    }
  }
  const Eigen::Vector3d gyro_std(0.042, 0.023, 0.017), accel_std(0.43, 0.58, 0.22);  // EuRoC V1_01 standstill
  const double sg = m.gyroSigma(), sa = m.accelSigma();
  ASSERT_EQ(real.imu.tones.size(), 2u);
  // A single-bin DFT of white noise of std s has an amplitude of about 2 s / sqrt(N).
  const double floor = 2.0 / std::sqrt(static_cast<double>(N));
  double largest_gyro_line = 0, largest_accel_line = 0;
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(stddev(g[i]), std::hypot(gyro_std[i], sg), 0.05 * gyro_std[i]) << "gyro axis " << i;
    EXPECT_NEAR(stddev(a[i]), std::hypot(accel_std[i], sa), 0.05 * accel_std[i]) << "accel axis " << i;
    for (const VibrationTone& t : real.imu.tones) {
      EXPECT_NEAR(lineAmplitude(g[i], t.frequency_hz), t.gyro_amplitude[i],
                  0.1 * t.gyro_amplitude[i] + 5 * floor * gyro_std[i])
          << "gyro axis " << i << " at " << t.frequency_hz << " Hz";
      EXPECT_NEAR(lineAmplitude(a[i], t.frequency_hz), t.accel_amplitude[i],
                  0.1 * t.accel_amplitude[i] + 5 * floor * accel_std[i])
          << "accel axis " << i << " at " << t.frequency_hz << " Hz";
      largest_gyro_line = std::max(largest_gyro_line, t.gyro_amplitude[i] / gyro_std[i]);
      largest_accel_line = std::max(largest_accel_line, t.accel_amplitude[i] / accel_std[i]);
    }
    // Between the lines only the broadband floor.
    EXPECT_LT(lineAmplitude(g[i], 40.0), 5 * floor * gyro_std[i]) << "gyro axis " << i;
    EXPECT_LT(lineAmplitude(a[i], 40.0), 5 * floor * accel_std[i]) << "accel axis " << i;
  }
  // The measured lines: gyro x at 17 Hz holds 39 % of its variance, accel x at 75 Hz 19 %.
  EXPECT_NEAR(real.imu.tones[0].gyro_amplitude.x(), std::sqrt(2 * 0.39) * gyro_std.x(), 1e-12);
  EXPECT_NEAR(real.imu.tones[1].accel_amplitude.x(), std::sqrt(2 * 0.19) * accel_std.x(), 1e-12);
  EXPECT_GT(largest_gyro_line, 0.5);
  EXPECT_GT(largest_accel_line, 0.5);
  EXPECT_NEAR(real.imu.tones[0].frequency_hz, 17.0, 1e-12);
  EXPECT_GE(real.imu.tones[1].frequency_hz, 72.0);
  EXPECT_LE(real.imu.tones[1].frequency_hz, 79.0);
}

// Without noise and vibration the readings are exactly M * truth, M within
// the scale and misalignment bounds and far from the identity.
TEST(Realism, ScaleFactorAndMisalignmentAreApplied) {
  const RealismProfile real = RealismProfile::real();
  ImuImperfections only;
  only.gyro_scale_bound = real.imu.gyro_scale_bound;
  only.accel_scale_bound = real.imu.accel_scale_bound;
  only.gyro_misalignment_bound = real.imu.gyro_misalignment_bound;
  only.accel_misalignment_bound = real.imu.accel_misalignment_bound;
  ImuSpec quiet;  // no white noise, bias or random walk
  ImuModel m(quiet, kRate, 9, true, false, only);
  for (const Eigen::Matrix3d* M : {&m.gyroMatrix(), &m.accelMatrix()}) {
    const double scale_bound = M == &m.gyroMatrix() ? only.gyro_scale_bound : only.accel_scale_bound;
    const double mis_bound = M == &m.gyroMatrix() ? only.gyro_misalignment_bound : only.accel_misalignment_bound;
    double largest_scale = 0, largest_cross = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const double e = std::abs((*M)(i, j) - (i == j ? 1.0 : 0.0));
        EXPECT_LE(e, i == j ? scale_bound : mis_bound) << i << "," << j;
        (i == j ? largest_scale : largest_cross) = std::max(i == j ? largest_scale : largest_cross, e);
      }
    EXPECT_GT(largest_scale, 0.2 * scale_bound);
    EXPECT_GT(largest_cross, 0.2 * mis_bound);
  }
  MotionSample turning = rest();
  turning.omega = Eigen::Vector3d(0.7, -1.3, 2.1);
  turning.a = Eigen::Vector3d(1.5, -0.4, 0.9);
  const ImuReading r = m.measure(turning);
  EXPECT_LT((r.gyro - m.gyroMatrix() * turning.omega).norm(), 1e-12);
  EXPECT_LT((r.accel - m.accelMatrix() * ImuModel::specificForce(turning)).norm(), 1e-12);
  EXPECT_GT((r.gyro - turning.omega).norm(), 1e-3);  // the errors are there
  // The ideal profile has none: the identity, readings untouched.
  ImuModel ideal(quiet, kRate, 9, true, false, RealismProfile::ideal().imu);
  EXPECT_EQ(ideal.gyroMatrix(), Eigen::Matrix3d::Identity());
  EXPECT_EQ(ideal.measure(turning).gyro, turning.omega);
}

// The ideal profile's IMU stream is the model's without imperfections, number for number.
TEST(Realism, IdealProfileLeavesTheImuStreamAsItWas) {
  ImuModel plain(ImuSpec::adis16448(), kRate, 4, true, true);
  ImuModel ideal(ImuSpec::adis16448(), kRate, 4, true, true, RealismProfile::ideal().imu);
  MotionSample moving = rest();
  moving.omega = Eigen::Vector3d(0.1, 0.2, -0.3);
  for (int n = 0; n < 100; ++n) {
    const ImuReading a = plain.measure(moving), b = ideal.measure(moving);
    ASSERT_EQ(a.gyro, b.gyro);
    ASSERT_EQ(a.accel, b.accel);
  }
}

// The filter is told an extrinsic 1.5 deg / 5 mm and a time offset 8 ms off;
// the truth (ground-truth calibration) is the default calibration exactly.
TEST(Realism, BelievedCalibrationIsOffByTheConfiguredAmountsTheTruthIsExact) {
  const RealismProfile real = RealismProfile::real();
  const CameraImuCalibration truth = CameraImuCalibration::makeDefault();
  EXPECT_GE(real.calibration.rotation_rad, 1.0 * kDeg);
  EXPECT_LE(real.calibration.rotation_rad, 2.0 * kDeg);
  EXPECT_GE(real.calibration.time_offset_s, 0.005);
  EXPECT_LE(real.calibration.time_offset_s, 0.010);
  Eigen::Vector3d first_shift = Eigen::Vector3d::Zero();
  for (uint32_t seed : {1u, 2u, 3u}) {
    const Scenario sc(smallConfig(Realism::Real, seed));
    const CameraImuCalibration& c = sc.calibration();
    EXPECT_EQ(c.T_cam_imu.p, truth.T_cam_imu.p);
    EXPECT_EQ(c.T_cam_imu.q.coeffs(), truth.T_cam_imu.q.coeffs());
    EXPECT_EQ(c.time_offset_ns, truth.time_offset_ns);
    const CameraImuCalibration& b = sc.believedCalibration();
    EXPECT_NEAR(angleBetween(b.T_cam_imu.q, c.T_cam_imu.q), real.calibration.rotation_rad, 1e-9);
    EXPECT_NEAR((b.T_cam_imu.p - c.T_cam_imu.p).norm(), real.calibration.translation_m, 1e-12);
    EXPECT_EQ(std::llabs(b.time_offset_ns - c.time_offset_ns), std::llround(real.calibration.time_offset_s * 1e9));
    // Camera stamps follow the true offset; the YAMLs say which is which.
    EXPECT_EQ(sc.frameStampNs(3), sc.frameTimeNs(3) - c.time_offset_ns);
    EXPECT_NE(sc.calibrationYaml().find("time_offset_s: -0.003\n"), std::string::npos) << sc.calibrationYaml();
    EXPECT_NE(sc.believedCalibrationYaml(), sc.calibrationYaml());
    const Eigen::Vector3d shift = b.T_cam_imu.p - c.T_cam_imu.p;
    if (seed == 1) first_shift = shift;
    else EXPECT_GT((shift - first_shift).norm(), 1e-4) << "direction not drawn from the seed";
  }
  const Scenario ideal(smallConfig(Realism::Ideal));
  EXPECT_EQ(ideal.believedCalibration().T_cam_imu.p, ideal.calibration().T_cam_imu.p);
  EXPECT_EQ(ideal.believedCalibration().time_offset_ns, ideal.calibration().time_offset_ns);
  EXPECT_EQ(ideal.believedCalibrationYaml(), ideal.calibrationYaml());
}

// The real profile's rig has EuRoC's lens, CameraInfo says so, and the
// simulator's projection (which the renderer inverts) equals OpenCV's.
TEST(Realism, RealLensProjectsAsOpenCvWithTheCameraInfosCoefficients) {
  const RealismProfile real = RealismProfile::real();
  const Scenario sc(smallConfig(Realism::Real));
  const CameraModel& cam = sc.rig().left;
  EXPECT_EQ(cam.k1, real.left_lens.k1);
  EXPECT_EQ(sc.rig().right.k1, real.right_lens.k1);
  EXPECT_LT(cam.k1, -0.25);
  const CameraInfoData info = sc.rig().leftInfo();
  EXPECT_EQ(info.distortion_model, "plumb_bob");
  ASSERT_EQ(info.D.size(), 5u);
  EXPECT_EQ(info.D[0], real.left_lens.k1);
  EXPECT_EQ(info.D[1], real.left_lens.k2);
  EXPECT_EQ(info.D[2], real.left_lens.p1);
  EXPECT_EQ(info.D[3], real.left_lens.p2);
  const cv::Mat K = (cv::Mat_<double>(3, 3) << info.K[0], info.K[1], info.K[2], info.K[3], info.K[4], info.K[5],
                     info.K[6], info.K[7], info.K[8]);
  const cv::Mat D(info.D, true);
  const std::vector<cv::Point3d> pts{{0.02, -0.01, 0.3}, {-0.15, 0.11, 0.35}, {0.17, 0.12, 0.3}, {0, 0, 1}};
  std::vector<cv::Point2d> ref;
  cv::projectPoints(pts, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, D, ref);
  double largest_shift = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    const Eigen::Vector3d X(pts[i].x, pts[i].y, pts[i].z);
    Eigen::Vector2d px;
    ASSERT_TRUE(project(X, Pose(), cam, &px));
    EXPECT_NEAR(px.x(), ref[i].x, 1e-6) << "point " << i;
    EXPECT_NEAR(px.y(), ref[i].y, 1e-6) << "point " << i;
    // The renderer's ray of that pixel points back at the point.
    EXPECT_LT((pixelToRay(cam, px) - X.normalized()).norm(), 1e-7) << "point " << i;
    const Eigen::Vector2d pinhole(cam.fx * X.x() / X.z() + cam.cx, cam.fy * X.y() / X.z() + cam.cy);
    largest_shift = std::max(largest_shift, (px - pinhole).norm());
  }
  EXPECT_GT(largest_shift, 0.5);  // the lens bends the corner points by pixels even at a tenth of the size
  // The ideal profile keeps the rig's mild lens.
  EXPECT_EQ(Scenario(smallConfig(Realism::Ideal)).rig().left.k1, StereoRigModel::makeDefault().left.k1);
}

TEST(Realism, OptionSelectsTheProfile) {
  ScenarioConfig c;
  EXPECT_EQ(c.realism, Realism::Ideal);
  EXPECT_TRUE(setScenarioOption("--realism", "real", &c));
  EXPECT_EQ(c.realism, Realism::Real);
  EXPECT_TRUE(setScenarioOption("--realism", "ideal", &c));
  EXPECT_EQ(c.realism, Realism::Ideal);
  EXPECT_THROW(setScenarioOption("--realism", "perfect", &c), std::invalid_argument);
  EXPECT_STREQ(realismName(Realism::Real), "real");
}
