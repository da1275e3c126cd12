// hapi_sim: how close to a real device a simulated recording is (make_sim_bag
// --realism ideal|real). "ideal" is the suite's historic sensor model (the
// ADIS16448 datasheet noise, a small turn-on bias, a mild lens, a calibration
// that the filter is told exactly). "real" makes the recording as hard as a
// real one: turn-on biases, scale factors and misalignment of real MEMS parts,
// platform vibration measured on a real standstill, a real lens (EuRoC's cam0)
// and a camera-IMU calibration that is a little wrong. Every value of the
// "real" profile is in RealismProfile::real() (realism.cpp), each with its
// source; docs/DESIGN.md "Data" lists them. ROS-free.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace hapi_sim {

enum class Realism { Ideal, Real };
bool parseRealism(const std::string& name, Realism* level);
const char* realismName(Realism level);

// A narrow-band vibration line: a sinusoid of this frequency on every axis
// (its phase per axis drawn from the seed). Amplitudes are peak values.
struct VibrationTone {
  double frequency_hz = 0;
  Eigen::Vector3d gyro_amplitude = Eigen::Vector3d::Zero();   // rad/s
  Eigen::Vector3d accel_amplitude = Eigen::Vector3d::Zero();  // m/s^2
};

// What a mounted MEMS IMU adds to the datasheet's noise model (ImuSpec).
// All zero: none (the ideal profile), and the IMU stream is bit-for-bit the
// historic one.
struct ImuImperfections {
  double gyro_turn_on_bound = 0;     // rad/s: bias per axis uniform in [-b, b]
  double accel_turn_on_bound = 0;    // m/s^2
  double gyro_scale_bound = 0;       // scale factor error per axis uniform in [-b, b] (fraction)
  double accel_scale_bound = 0;
  double gyro_misalignment_bound = 0;   // rad: each cross-axis term uniform in [-b, b]
  double accel_misalignment_bound = 0;
  std::vector<VibrationTone> tones;
  // Broadband vibration (white, on top of the datasheet white noise).
  Eigen::Vector3d gyro_broadband_density = Eigen::Vector3d::Zero();   // rad/s/sqrt(Hz)
  Eigen::Vector3d accel_broadband_density = Eigen::Vector3d::Zero();  // m/s^2/sqrt(Hz)
  bool any() const;
};

// How wrong the camera-IMU calibration that the filter is told is: the
// believed extrinsic is the true one turned by rotation_rad about a
// seed-drawn axis and moved by translation_m along a seed-drawn direction;
// the believed time offset is the true one +- time_offset_s (sign from the seed).
struct CalibrationError {
  double rotation_rad = 0;
  double translation_m = 0;
  double time_offset_s = 0;
  bool any() const { return rotation_rad != 0 || translation_m != 0 || time_offset_s != 0; }
};

// Radial-tangential lens (k1 k2 p1 p2 k3 of OpenCV / ROS plumb_bob).
struct LensDistortion {
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
};

struct RealismProfile {
  Realism level = Realism::Ideal;
  ImuImperfections imu;
  CalibrationError calibration;
  bool real_lens = false;   // false: the rig's own mild lens (StereoRigModel::makeDefault)
  LensDistortion left_lens, right_lens;
  static RealismProfile ideal();
  static RealismProfile real();
  static RealismProfile forLevel(Realism level);
};

}  // namespace hapi_sim
