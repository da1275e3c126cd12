// DenseDepthNodelet: dense depth with confidence per stereo keyframe
// (docs/DESIGN.md "Dense depth"), the thin ROS wrapper of
// DenseDepthProcessor.
//
// In (the front end's names, remapped the same way): left/image_raw,
// right/image_raw (image_transport, ~image_transport), left/camera_info,
// right/camera_info, exact or approximate stamp sync (~approximate_sync).
// The images are the raw pair; they are rectified here from the CameraInfo.
// Out, at most ~rate per second, each with the left image's header:
//   ~depth        sensor_msgs/Image 32FC1, metres along the optical axis, NaN invalid
//   ~confidence   sensor_msgs/Image mono8, confidence * 255
//   ~camera_info  the depth image's pinhole camera (rectified, scaled by ~image_scale)
//
// Threading: the synchronised callback only applies the keyframe gate and
// posts the pair into a newest-wins mailbox (an overwritten pair counts as
// dropped.busy); a worker thread owned by the nodelet matches and publishes,
// so a slow keyframe never holds a manager thread.
// Bad input: a rate-limited error per reason and a diagnostics counter, never
// a crash. Invalid parameters: refuses to run (StartupFailure).
#pragma once

#include "dense_depth_nodelet_diagnostics.hpp"
#include "dense_depth_nodelet_params.hpp"
#include "dense_depth_nodelet_processor.hpp"
#include "reason_throttle.hpp"
#include "stereo_pair_input.hpp"

#include "hapi_surface/dense_depth_keyframe_gate.hpp"

#include <diagnostic_updater/diagnostic_updater.h>
#include <hapi_nodelet_kit/mailbox.hpp>
#include <hapi_nodelet_kit/startup_failure.hpp>
#include <nodelet/nodelet.h>
#include <ros/ros.h>

#include <memory>
#include <thread>

namespace hapi_surface {

class DenseDepthNodelet : public nodelet::Nodelet {
 public:
  DenseDepthNodelet() = default;
  ~DenseDepthNodelet() override;

 private:
  struct Pair {
    sensor_msgs::ImageConstPtr left, right;
    sensor_msgs::CameraInfoConstPtr left_info, right_info;
  };

  void onInit() override;
  void startDiagnostics();
  void onSynced(const sensor_msgs::ImageConstPtr& l, const sensor_msgs::CameraInfoConstPtr& li,
                const sensor_msgs::ImageConstPtr& r, const sensor_msgs::CameraInfoConstPtr& ri);
  void workerLoop();
  void processPair(const Pair& p);
  void reject(const std::string& reason, const std::string& detail);

  static constexpr const char* kStatusName = "dense depth";
  static constexpr const char* kHardwareId = "dense_depth";

  DenseDepthNodeletParams params_;
  std::unique_ptr<DenseDepthProcessor> processor_;  // worker only
  std::unique_ptr<DenseDepthKeyframeGate> gate_;    // sync callback only
  hapi_nodelet_kit::StartupFailure startup_{kStatusName, kHardwareId};
  DenseDepthDiagnostics diag_;
  hapi_frontend::ReasonThrottle error_log_{2.0};
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  ros::WallTimer diag_timer_;
  ros::Publisher depth_pub_, confidence_pub_, info_pub_;

  hapi_frontend::StereoPairInput input_;

  hapi_nodelet_kit::Mailbox<Pair> mailbox_;
  std::thread worker_;
};

}  // namespace hapi_surface
