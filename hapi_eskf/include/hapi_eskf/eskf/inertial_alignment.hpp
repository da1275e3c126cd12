// The inertial model's start (docs/DESIGN.md "Inertial initialisation"): the
// IMU samples of the first alignment_window seconds give the direction of
// gravity, so the filter's world (the published map frame) is gravity-aligned,
// z up (REP-103); its origin is the first camera position and its yaw the
// smallest rotation that levels the body.
//  * Still start (imuWindowStats below): the mean gyro is the gyro bias (1
//    sigma: its standard error), the velocity is zero with
//    static_sigma_velocity.
//  * Moving start: the mean specific force still points up to within the
//    mean acceleration over the window (a hand's motion averages out), so
//    gravity gets a 1 sigma of the accelerometer's spread over the window
//    when that exceeds initial_sigma_gravity; the gyro bias starts at zero
//    (initial_sigma_gyro_bias); the velocity is the one whose mean over the
//    window is zero (the hand moves about a place: ImuWindowStats::
//    velocity_end), with initial_sigma_velocity. The first visual updates
//    determine them, since the landmarks' apparent motion measures the
//    camera's velocity and tilt.
// Either way the gravity vector stays a state with initial_sigma_gravity per
// component (the tilt's uncertainty, mostly the unknown accelerometer bias).
#pragma once

#include "hapi_eskf/eskf/motion_model.hpp"
#include "hapi_eskf/status.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace hapi_eskf {

// A window of IMU samples: its means and spreads. Two questions are asked of
// it, with the same statistics:
//  * stillStart (the alignment): was the device at rest, so that the mean
//    gyro is its bias and the velocity zero? Real platforms vibrate: a MAV
//    standing on the ground shows 0.02-0.04 rad/s and 0.2-0.6 m/s^2 of sample
//    spread at 200 Hz (fans, motors: 17 Hz and 75 Hz on EuRoC's ADIS16448),
//    10-20x a datasheet's white noise, yet its velocity wanders by a few
//    mm/s. So rest is judged on the velocity the accelerometer integrates to
//    (its RMS deviation within the window), not on the raw sample spread.
//  * heldStill (scene motion): is a hand holding the device still? The
//    gyro's RMS about the filter's bias and the raw accelerometer spread,
//    loose enough for tremor (held_*_threshold).
constexpr int kStillBlocks = 3;
struct ImuWindowStats {
  Vec3 gyro_mean = Vec3::Zero(), accel_mean = Vec3::Zero();
  double gyro_rms = 0.0;      // about the given bias [rad/s]
  // RMS deviation of the means of kStillBlocks consecutive blocks from the
  // window's mean, all axes [rad/s]: the slow part of the rate (a hand's
  // sway); vibration averages out within a block.
  double gyro_block_spread = 0.0;
  double accel_spread = 0.0;  // RMS deviation from the mean, all axes [m/s^2]
  // RMS deviation of v(t) = integral of (f - mean f) dt from its own mean:
  // how much the velocity changed within the window [m/s].
  double velocity_rms = 0.0;
  // v(T) minus the mean of v(t) over the window [m/s], body axes: the
  // velocity at the window's end if the mean velocity over the window is
  // zero (a hand's motion about a place; no rotation over the window).
  Vec3 velocity_end = Vec3::Zero();
  // Least-squares rate of change of the specific force over the window
  // [m/s^3]: a turn at rate w rotates gravity in the body frame,
  // df/dt = -w x f; a gyro bias does not.
  Vec3 accel_slope = Vec3::Zero();
  double accel_slope_sigma = 0.0;  // its standard error per axis, from the spread [m/s^3]
  int samples = 0;
};
template <typename Iterator>
ImuWindowStats imuWindowStats(Iterator begin, Iterator end, const Vec3& gyro_bias);

// At rest (docs/DESIGN.md "Inertial initialisation"): the velocity changed
// by less than the zero velocity's own sigma (static_sigma_velocity), the
// mean rate is no larger than a turn-on bias can be (static_gyro_threshold),
// the specific force's change over the window does not fit a turn at the
// mean rate better than a bias (no change) where the two differ by more
// than twice the change's standard error (-w x f: a steady turn moves no
// velocity, but it rotates gravity in the body frame; a turn about gravity
// itself, or one that vibration hides, cannot be told from a bias and is
// taken for one), and the mean specific force is within
// static_accel_threshold of gravity (no steady acceleration along it).
bool stillStart(const ImuWindowStats& w, const EskfSettings& s);
// Held by a hand: the gyro's RMS about the bias below held_gyro_threshold,
// the accelerometer's spread and |mean f| - g below held_accel_threshold.
bool heldStill(const ImuWindowStats& w, const EskfSettings& s);

struct InertialStart {
  NominalState x;  // at the stamp of the window's last sample
  PoseMat C;       // 18 x 18
  ImuWindowStats window;  // the alignment window, about a zero gyro bias
  bool still = false;     // a still start (stillStart)
};

// `window`: increasing stamps, at least 2 samples; the model must be the
// inertial one. kInvalidArgument otherwise, kNonFinite for a non-finite
// sample, kEmptyInput when the mean specific force is too small to give a
// direction (free fall, a dead accelerometer).
Status alignInertialStart(const std::vector<ImuSample>& window, const MotionModel& model, const EskfSettings& s,
                          InertialStart* out);

template <typename Iterator>
ImuWindowStats imuWindowStats(Iterator begin, Iterator end, const Vec3& gyro_bias) {
  ImuWindowStats r;
  double n = 0.0, w2 = 0.0;
  for (Iterator it = begin; it != end; ++it) {
    r.gyro_mean += it->gyro;
    r.accel_mean += it->accel;
    w2 += (it->gyro - gyro_bias).squaredNorm();
    n += 1.0;
  }
  r.samples = static_cast<int>(n);
  if (n < 2.0) return r;
  r.gyro_mean /= n;
  r.accel_mean /= n;
  // Spreads, and the velocity change integrated with each sample held over
  // the interval before it (the first sample opens the window).
  double f2 = 0.0;
  Vec3 v = Vec3::Zero(), v_sum = Vec3::Zero();
  double v2 = 0.0, prev = begin->stamp, t_mean = 0.0;
  for (Iterator it = begin; it != end; ++it) t_mean += it->stamp / n;
  Vec3 tf = Vec3::Zero();
  double tt = 0.0;
  Vec3 block[kStillBlocks] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  double block_n[kStillBlocks] = {0.0, 0.0, 0.0}, i = 0.0;
  for (Iterator it = begin; it != end; ++it, i += 1.0) {
    const int b = std::min(kStillBlocks - 1, static_cast<int>(i * kStillBlocks / n));
    block[b] += it->gyro;
    block_n[b] += 1.0;
    f2 += (it->accel - r.accel_mean).squaredNorm();
    tf += (it->stamp - t_mean) * (it->accel - r.accel_mean);
    tt += (it->stamp - t_mean) * (it->stamp - t_mean);
    v += (it->accel - r.accel_mean) * (it->stamp - prev);
    prev = it->stamp;
    v_sum += v;
    v2 += v.squaredNorm();
  }
  r.gyro_rms = std::sqrt(w2 / n);
  double g2 = 0.0, blocks = 0.0;
  for (int b = 0; b < kStillBlocks; ++b)
    if (block_n[b] > 0.0) {
      g2 += (block[b] / block_n[b] - r.gyro_mean).squaredNorm();
      blocks += 1.0;
    }
  r.gyro_block_spread = std::sqrt(g2 / blocks);
  r.accel_spread = std::sqrt(f2 / n);
  r.velocity_rms = std::sqrt(std::max(0.0, v2 / n - (v_sum / n).squaredNorm()));
  r.velocity_end = v - v_sum / n;
  if (tt > 0.0) {
    r.accel_slope = tf / tt;
    r.accel_slope_sigma = r.accel_spread / std::sqrt(3.0 * tt);
  }
  return r;
}

}  // namespace hapi_eskf
