// ImagingFlowNodelet: the thin ROS wrapper of hapi_frontend::ImageFlowTracker
// (docs/DESIGN.md "Surface motion: image flow").
//
// In: `image` (sensor_msgs/Image through image_transport, ~image_transport;
// mono8, mono16, bgr8, rgb8, bgra8, 32FC1). Out: `~flow` (hapi_msgs/ImageFlow,
// header = the image's: stamp of the later frame, frame_id its optical
// frame), one message per image, including the restarts (STATUS_FIRST_FRAME)
// so consumers see them.
//
// Threading: the tracker runs in the image callback (a few milliseconds on
// a window about the pixel): every frame is needed in order, so there is no
// newest-wins mailbox, and the flow leaves with the least latency. roscpp
// never runs one subscription's callback concurrently; the mutex only
// guards against a resubscription.
//
// Bad input (unsupported encoding, truncated buffer, size change, missing
// frame_id): a rate-limited error per reason and a diagnostics counter,
// never a crash; the tracker restarts where the input breaks its sequence.
// Invalid parameters: refuses to run (hapi_nodelet_kit::StartupFailure).
#pragma once

#include "imaging_flow_diagnostics.hpp"
#include "imaging_flow_params.hpp"
#include "reason_throttle.hpp"

#include "hapi_frontend/image_flow_tracker.hpp"

#include <diagnostic_updater/diagnostic_updater.h>
#include <hapi_nodelet_kit/startup_failure.hpp>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>

#include <memory>
#include <mutex>

namespace hapi_frontend {

class ImagingFlowNodelet : public nodelet::Nodelet {
 public:
  ImagingFlowNodelet() = default;
  ~ImagingFlowNodelet() override;

 private:
  void onInit() override;
  void startDiagnostics();
  void onImage(const sensor_msgs::ImageConstPtr& image);
  void badImage(const std::string& reason, const std::string& detail);

  static constexpr const char* kStatusName = "imaging flow";
  static constexpr const char* kHardwareId = "imaging_flow";

  ImagingFlowNodeletParams params_;
  std::unique_ptr<ImageFlowTracker> tracker_;
  std::mutex tracker_mutex_;
  hapi_nodelet_kit::StartupFailure startup_{kStatusName, kHardwareId};
  ImagingFlowDiagnostics diag_;
  ReasonThrottle error_log_{2.0};
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  ros::WallTimer diag_timer_;
  ros::Publisher pub_;
  std::unique_ptr<image_transport::ImageTransport> it_;
  image_transport::Subscriber sub_;
};

}  // namespace hapi_frontend
