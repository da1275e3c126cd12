// The filter side shared by the back-end fuzz targets: a small filter (CPU
// backend, pool of 32 landmarks) driven the way EskfNodelet's worker drives
// it (created by the first frame with landmarks, reset at the first frame
// after a reset request, predictTo for a frame without landmarks, IMU
// samples up to each frame first). Every call's Status is a legal outcome;
// the fuzzer looks for crashes, sanitizer reports, hangs and non-finite
// states the filter accepted.
#pragma once

#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "hapi_eskf/eskf/eskf.hpp"
#include "hapi_eskf/eskf/storage_factory.hpp"

#include <ros/console.h>
#include <ros/time.h>

#include <cstdio>
#include <cstdlib>
#include <memory>

namespace hapi_fuzz {

// Small enough for thousands of iterations per second, large enough that
// the pool fills and evicts within a few frames.
constexpr int kPoolSize = 32;
constexpr std::uint32_t kMaxMeasurements = 64;

// The nodelet code logs through rosconsole (throttled, with ros::Time):
// the clock is initialised and only fatal messages are printed.
inline void quietRosConsole() {
  ros::Time::init();
  if (ros::console::set_logger_level(ROSCONSOLE_ROOT_LOGGER_NAME, ros::console::levels::Fatal))
    ros::console::notifyLoggerLevelsChanged();
}

inline hapi_eskf::EskfSettings fuzzSettings(hapi_eskf::MotionModelKind model) {
  hapi_eskf::EskfSettings s;
  s.max_landmarks = kPoolSize;
  s.bootstrap_landmarks = 16;
  s.max_new_landmarks = 8;
  s.max_update_landmarks = 16;
  s.max_frame_measurements = static_cast<int>(kMaxMeasurements);
  s.ransac_iterations = 10;
  s.motion_model = model;
  return s;
}

class FilterUnderTest {
 public:
  explicit FilterUnderTest(hapi_eskf::MotionModelKind model) : settings_(fuzzSettings(model)) {}

  void requestReset() { need_init_ = true; }

  // An IMU sample on the camera clock (already through the input checks).
  void imu(const hapi_eskf::ImuSample& s) {
    if (!eskf_ || need_init_ || s.stamp <= eskf_->time()) return;
    eskf_->addImu(s);
    checkFinite();
  }

  void frame(const hapi_eskf::StereoFrame& f) {
    if (!eskf_) {
      if (f.measurements.empty()) return;  // the descriptor length is not known yet
      std::string err;
      auto backend = hapi_eskf::makeBackend(settings_, f.descriptor_length, &err);
      if (!backend) {
        std::fprintf(stderr, "backend creation failed: %s\n", err.c_str());
        std::abort();  // the settings are fixed and valid: never expected
      }
      eskf_ = std::make_unique<hapi_eskf::Eskf>(settings_, std::move(backend));
    }
    if (need_init_) {
      if (eskf_->reset(hapi_eskf::PoseState(), f.stamp) != hapi_eskf::Status::kOk) return;
      need_init_ = false;
    }
    if (f.measurements.empty())
      eskf_->predictTo(f.stamp);
    else
      eskf_->processFrame(f);
    checkFinite();
  }

  const hapi_eskf::Eskf* eskf() const { return eskf_.get(); }

 private:
  // A state the filter accepted must be finite (it reports non-finite
  // results as a Status and keeps the old state).
  void checkFinite() const {
    const hapi_eskf::PoseState p = eskf_->pose();
    if (!p.p.allFinite() || !p.q.coeffs().allFinite()) {
      std::fprintf(stderr, "non-finite filter pose\n");
      std::abort();
    }
  }

  hapi_eskf::EskfSettings settings_;
  std::unique_ptr<hapi_eskf::Eskf> eskf_;
  bool need_init_ = true;
};

}  // namespace hapi_fuzz
