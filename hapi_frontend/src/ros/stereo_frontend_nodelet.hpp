// StereoFrontendNodelet: the thin ROS wrapper of hapi_frontend::StereoPipeline.
//
// Threading: the four input subscriptions (left/right image via
// image_transport, left/right CameraInfo) live on the nodelet manager's
// multi-threaded queue; their synchronised callback only checks stamps
// (hapi_nodelet_kit::StampGuard) and posts the frame into a
// hapi_nodelet_kit::Mailbox (newest wins; an overwritten frame is counted as
// dropped.busy). A worker thread owned by this nodelet runs the pipeline and
// publishes, so a slow frame never holds a manager thread that other nodelets
// (the ES-EKF back end) need.
//
// Start-up: invalid parameters, a pipeline that cannot be built or a missing
// image_transport plugin make it refuse to run (hapi_nodelet_kit::
// StartupFailure: FATAL log, ERROR on /diagnostics, nothing subscribed).
#pragma once

#include "frontend_diagnostics.hpp"
#include "frontend_self_check.hpp"
#include "frontend_params.hpp"
#include "reason_throttle.hpp"
#include "stereo_pair_input.hpp"
#include "hapi_frontend/stereo_pipeline.hpp"

#include <diagnostic_updater/diagnostic_updater.h>
#include <hapi_nodelet_kit/mailbox.hpp>
#include <hapi_nodelet_kit/stamp_guard.hpp>
#include <hapi_nodelet_kit/startup_failure.hpp>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <map>
#include <memory>
#include <mutex>
#include <thread>

namespace hapi_frontend {

class StereoFrontendNodelet : public nodelet::Nodelet {
 public:
  StereoFrontendNodelet() = default;
  ~StereoFrontendNodelet() override;

 private:
  using Info = sensor_msgs::CameraInfo;

  struct Frame {
    sensor_msgs::ImageConstPtr left, right;
    sensor_msgs::CameraInfoConstPtr left_info, right_info;
  };

  void onInit() override;
  // onInit's steps after the parameters; false after a refusal.
  bool subscribeImages(ros::NodeHandle& nh, ros::NodeHandle& pnh);
  void startDiagnostics();
  void onSynced(const sensor_msgs::ImageConstPtr& l, const sensor_msgs::CameraInfoConstPtr& li,
                const sensor_msgs::ImageConstPtr& r, const sensor_msgs::CameraInfoConstPtr& ri);
  void onExactDrop(const sensor_msgs::ImageConstPtr& l, const sensor_msgs::CameraInfoConstPtr& li,
                   const sensor_msgs::ImageConstPtr& r, const sensor_msgs::CameraInfoConstPtr& ri);
  void workerLoop();
  void processFrame(const Frame& f);
  // Rebuilds the camera models only when the CameraInfo pair changed.
  bool updateCalibration(const Info& left, const Info& right);
  void reject(const std::string& reason, const std::string& detail);

  // The diagnostic task's name, shared by the running and the refusing node.
  static constexpr const char* kStatusName = "stereo front end";
  static constexpr const char* kHardwareId = "stereo_frontend";
  static constexpr const char* kSelfCheckName = "stereo front end self-check";

  FrontendNodeletParams params_;
  std::unique_ptr<StereoPipeline> pipeline_;
  hapi_nodelet_kit::StartupFailure startup_{kStatusName, kHardwareId};
  FrontendDiagnostics diag_;
  std::unique_ptr<FrontendSelfCheck> self_check_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  ros::WallTimer diag_timer_;
  ros::Publisher pub_;

  StereoPairInput input_;

  // Stamp order of the synchronised callback (~time_jump_reset).
  std::unique_ptr<hapi_nodelet_kit::StampGuard> stamp_guard_;

  // Between the synchronised callback and the worker.
  hapi_nodelet_kit::Mailbox<Frame> mailbox_;
  std::thread worker_;

  // Per-reason rate limit of the rejection log (one per 2 s).
  ReasonThrottle error_log_{2.0};

  // Worker-only state.
  Info calib_left_, calib_right_;
  bool calib_ok_ = false;
  bool warned_no_gpu_ = false;
};

}  // namespace hapi_frontend
