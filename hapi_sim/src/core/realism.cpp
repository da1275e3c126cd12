// The realism profiles (realism.hpp): the one table of the "real" profile's
// values and their sources.
#include "hapi_sim/realism.hpp"

#include <cmath>

namespace hapi_sim {
namespace {

constexpr double kDeg = M_PI / 180.0;

// The standstill of EuRoC V1_01 (ADIS16448 on the MAV standing on the ground,
// shared/data/euroc_v1_01_static): per-axis standard deviation at 200 Hz of
// the readings about their mean. 7-20x the datasheet white noise: platform
// vibration, with spectral peaks near 17 Hz and 72-79 Hz.
const Eigen::Vector3d kStandstillGyroStd(0.042, 0.023, 0.017);  // rad/s
const Eigen::Vector3d kStandstillAccelStd(0.43, 0.58, 0.22);    // m/s^2
constexpr double kStandstillRateHz = 200.0;
// The two lines and the share of each axis' variance in them, measured on
// the standstill's 4.75 s (Hann window) as the power in 15-19 Hz and in
// 70-81 Hz; the rest (a floor with smaller peaks at 19-24 Hz and 90 Hz) is
// white noise here.
struct Line {
  double hz;
  Eigen::Vector3d gyro_share, accel_share;
};
const Line kLines[] = {
    {17.0, {0.39, 0.07, 0.10}, {0.02, 0.24, 0.03}},  // 15-19 Hz
    {75.0, {0.00, 0.09, 0.03}, {0.19, 0.01, 0.05}},  // 70-81 Hz (75: its middle)
};

// A sine of amplitude A has variance A^2 / 2; white noise of std s at the
// measurement rate has the density s / sqrt(rate).
void standstillVibration(ImuImperfections* imu) {
  Eigen::Vector3d gyro_rest = Eigen::Vector3d::Ones(), accel_rest = Eigen::Vector3d::Ones();
  for (const Line& l : kLines) {
    imu->tones.push_back({l.hz, (2.0 * l.gyro_share).cwiseSqrt().cwiseProduct(kStandstillGyroStd),
                          (2.0 * l.accel_share).cwiseSqrt().cwiseProduct(kStandstillAccelStd)});
    gyro_rest -= l.gyro_share;
    accel_rest -= l.accel_share;
  }
  imu->gyro_broadband_density = gyro_rest.cwiseSqrt().cwiseProduct(kStandstillGyroStd) / std::sqrt(kStandstillRateHz);
  imu->accel_broadband_density = accel_rest.cwiseSqrt().cwiseProduct(kStandstillAccelStd) / std::sqrt(kStandstillRateHz);
}

}  // namespace

bool parseRealism(const std::string& name, Realism* level) {
  if (name == "ideal") { *level = Realism::Ideal; return true; }
  if (name == "real") { *level = Realism::Real; return true; }
  return false;
}

const char* realismName(Realism level) { return level == Realism::Real ? "real" : "ideal"; }

bool ImuImperfections::any() const {
  return gyro_turn_on_bound != 0 || accel_turn_on_bound != 0 || gyro_scale_bound != 0 || accel_scale_bound != 0 ||
         gyro_misalignment_bound != 0 || accel_misalignment_bound != 0 || !tones.empty() ||
         !gyro_broadband_density.isZero() || !accel_broadband_density.isZero();
}

RealismProfile RealismProfile::ideal() { return RealismProfile(); }

RealismProfile RealismProfile::real() {
  RealismProfile p;
  p.level = Realism::Real;
  ImuImperfections& imu = p.imu;
  // Turn-on bias, uniform per axis. Gyro 0.1 rad/s (5.7 deg/s): below the
  // uncalibrated MPU-6000's initial ZRO tolerance of +-20 deg/s (InvenSense
  // PS-MPU-6000A-00 rev. 3.4, table 6.1), above a factory-calibrated part's
  // ~1 deg/s (BMI088 class); it covers the EuRoC standstill's measured
  // (-0.002, 0.021, 0.078) rad/s. Accelerometer 0.2 m/s^2 (20 mg): the MPU-6000
  // allows +-50 mg (x, y) and +-80 mg (z) zero-g tolerance (table 6.2), a
  // calibrated part ~20 mg (BMI088 class).
  imu.gyro_turn_on_bound = 0.1;
  imu.accel_turn_on_bound = 0.2;
  // Scale factor error per axis, +-1 %: a factory-calibrated part's
  // sensitivity tolerance (ADIS16448 / BMI088 class); the uncalibrated
  // MPU-6000 allows +-3 % (gyro scale factor tolerance, table 6.1;
  // accelerometer initial calibration tolerance, table 6.2).
  imu.gyro_scale_bound = 0.01;
  imu.accel_scale_bound = 0.01;
  // Axis misalignment, +-1 deg per cross-axis term: the MPU-6000's
  // cross-axis sensitivity of +-2 % (1.1 deg; tables 6.1 and 6.2); a
  // board-mounted part adds its own tilt.
  imu.gyro_misalignment_bound = 1.0 * kDeg;
  imu.accel_misalignment_bound = 1.0 * kDeg;
  standstillVibration(&imu);
  // Calibration that the filter is told (the bag's /tf_static and
  // /calibration): a hand-eye calibration or a CAD extrinsic is typically off
  // by 1-2 deg and a few mm, an unsynchronised camera-IMU clock by 5-10 ms.
  p.calibration.rotation_rad = 1.5 * kDeg;
  p.calibration.translation_m = 0.005;
  p.calibration.time_offset_s = 0.008;
  // EuRoC's MT9M034 lenses, radial-tangential
  // (shared/data/euroc_v1_01_static/mav0/cam{0,1}/sensor.yaml).
  p.real_lens = true;
  p.left_lens = {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05, 0.0};
  p.right_lens = {-0.28368365, 0.07451284, -0.00010473, -3.55590700e-05, 0.0};
  return p;
}

RealismProfile RealismProfile::forLevel(Realism level) { return level == Realism::Real ? real() : ideal(); }

}  // namespace hapi_sim
