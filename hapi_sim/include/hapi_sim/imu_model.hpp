// hapi_sim: the simulated IMU: ideal gyro (body angular rate) and
// accelerometer (specific force R^T (a - g), gravity along -z of the inertial
// frame), plus white noise, turn-on bias, bias random walk and optional
// saturation of a real MEMS part, and optionally what a mounted part adds
// (ImuImperfections of the realism profile: turn-on bias, scale factor,
// misalignment, vibration; docs/DESIGN.md "Data").
#pragma once
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <vector>

#include "hapi_sim/globe_sim.hpp"
#include "hapi_sim/motion.hpp"
#include "hapi_sim/realism.hpp"

namespace hapi_sim {

constexpr double kGravity = 9.81;  // m/s^2, along -z of the inertial frame (as make_globe_bag)

// Continuous-time noise model (Kalibr / EuRoC units).
struct ImuSpec {
  const char* part = "";
  double gyro_noise_density = 0;   // rad/s/sqrt(Hz)
  double gyro_random_walk = 0;     // rad/s^2/sqrt(Hz)
  double accel_noise_density = 0;  // m/s^2/sqrt(Hz)
  double accel_random_walk = 0;    // m/s^3/sqrt(Hz)
  double gyro_turn_on_sigma = 0;   // rad/s, bias at power-on (per axis)
  double accel_turn_on_sigma = 0;  // m/s^2
  double gyro_range = 0;           // rad/s, saturation
  double accel_range = 0;          // m/s^2
  // Analog Devices ADIS16448, the IMU of the EuRoC MAV data sets.
  static ImuSpec adis16448();
};

struct ImuReading {
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();        // rad/s, IMU frame
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();       // m/s^2, IMU frame
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();   // true bias in this reading
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();
};

// Samples at a fixed rate, in order: each measure() adds the current bias and
// white noise of standard deviation density * sqrt(rate), then advances the
// bias by a random-walk step of random_walk / sqrt(rate). With imperfections
// (and noise on), sample n reads M (ideal) + bias + white noise + vibration
// at t = n / rate, M = I + scale + misalignment; the imperfections come from
// a random stream of their own, so the datasheet noise stays as without them.
class ImuModel {
 public:
  ImuModel(const ImuSpec& spec, double rate_hz, uint32_t seed, bool noise, bool saturate,
           const ImuImperfections& imperfections = ImuImperfections());
  // Ideal specific force of the IMU frame (motion of the IMU in the inertial frame).
  static Eigen::Vector3d specificForce(const MotionSample& imu);
  ImuReading measure(const MotionSample& imu);
  double gyroSigma() const { return spec_.gyro_noise_density * std::sqrt(rate_); }
  double accelSigma() const { return spec_.accel_noise_density * std::sqrt(rate_); }
  const ImuSpec& spec() const { return spec_; }
  // M of the gyro / accelerometer: reading = M * true + ... (identity without imperfections).
  const Eigen::Matrix3d& gyroMatrix() const { return Mg_; }
  const Eigen::Matrix3d& accelMatrix() const { return Ma_; }

 private:
  ImuSpec spec_;
  double rate_;
  bool noise_, saturate_;
  GaussianRng rng_;
  Eigen::Vector3d bg_ = Eigen::Vector3d::Zero(), ba_ = Eigen::Vector3d::Zero();
  ImuImperfections imp_;
  bool imperfect_ = false;
  GaussianRng imp_rng_;
  Eigen::Matrix3d Mg_ = Eigen::Matrix3d::Identity(), Ma_ = Eigen::Matrix3d::Identity();
  std::vector<Eigen::Matrix<double, 6, 1>> phases_;  // per tone: gyro xyz, accel xyz (rad)
  int64_t n_ = 0;  // samples measured

  void drawImperfections();
  void addVibration(ImuReading* r);
};

}  // namespace hapi_sim
