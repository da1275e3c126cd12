// The IMU's in-situ white-noise density, measured online from its own
// samples (docs/DESIGN.md "In-situ IMU noise"). A datasheet's density
// describes the sensor on a quiet bench; on a vibrating platform (a MAV's
// motors, a hand-held device's fan) the samples spread 10-20x more, and a
// filter that believes the datasheet is overconfident. The estimate works at
// rest and in motion: per axis, the third difference of consecutive samples,
//   d[i] = x[i] - 3 x[i-1] + 3 x[i-2] - x[i-3],
// has variance 20 sigma^2 for white noise of per-sample std sigma, while the
// motion a hand makes (up to tremor at 8-12 Hz) is a smooth function sampled
// at 200 Hz whose third difference is tiny (DESIGN.md gives the numbers);
// density = sigma sqrt(dt), dt the sample interval. Over a sliding window of
// imu_noise_window seconds; the filter predicts with the larger of the
// datasheet's and this (motion_model.hpp imuNoiseDensities).
#pragma once

#include "hapi_eskf/eskf/motion_model.hpp"
#include "hapi_eskf/types.hpp"

#include <deque>

namespace hapi_eskf {

class ImuNoiseEstimator {
 public:
  // Fewest third differences behind an estimate: with 50 the density's
  // relative standard error is about 15 % (DESIGN.md), and the inertial
  // model's alignment window (0.3 s: 57 differences at 200 Hz) measures the
  // noise before the first prediction (a filter that starts on the
  // datasheet's noise starts overconfident).
  static constexpr int kMinDifferences = 50;

  explicit ImuNoiseEstimator(double window_s) : window_(window_s) {}

  // A sample as read (stamps increasing; an earlier stamp restarts the
  // window: a bag loop, a reset; a repeated stamp is ignored).
  void add(const ImuSample& sample);
  void clear() { samples_.clear(); }

  // The densities over the window, per IMU axis; zero (not measured) while
  // fewer than kMinDifferences differences are usable. A difference whose
  // three intervals are not all within [0.5, 1.5] of the window's mean
  // interval (a dropped sample, a gap) is left out: across unequal
  // intervals the motion no longer cancels.
  ImuNoiseDensity estimate() const;

 private:
  double window_;
  std::deque<ImuSample> samples_;
};

}  // namespace hapi_eskf
