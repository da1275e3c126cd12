// ImagingFlowNodelet (imaging_flow_nodelet.hpp): start-up and the image
// callback.
#include "imaging_flow_nodelet.hpp"

#include "flow_message.hpp"

#include <hapi_msgs/ImageFlow.h>
#include <pluginlib/class_list_macros.hpp>

#include <boost/make_shared.hpp>

#include <chrono>

namespace hapi_frontend {

ImagingFlowNodelet::~ImagingFlowNodelet() {
  diag_timer_.stop();
  sub_.shutdown();  // waits for a running callback
}

void ImagingFlowNodelet::onInit() {
  ros::NodeHandle& nh = getMTNodeHandle();
  ros::NodeHandle& pnh = getMTPrivateNodeHandle();
  hapi_nodelet_kit::ParamReader reader(pnh);
  readImagingFlowParams(reader, &params_);
  for (const auto& w : reader.warnings()) NODELET_WARN("%s", w.c_str());
  if (!reader.ok())
    return startup_.refuse(getNodeHandle(), getPrivateNodeHandle(), getName(), "invalid parameters",
                           reader.errors());
  tracker_ = std::make_unique<ImageFlowTracker>(params_.flow);  // parameters validated above
  // ~use_gpu without a usable CUDA device (or in a build without CUDA): the
  // CPU tracker runs, and the user is told why once, as an error.
  diag_.backend(tracker_->backendStatus());
  if (params_.flow.use_gpu && !tracker_->usingGpu())
    NODELET_ERROR("imaging flow: ~use_gpu is set but the CUDA tracker cannot run: %s",
                  tracker_->backendStatus().c_str());
  pub_ = pnh.advertise<hapi_msgs::ImageFlow>("flow", 20);
  it_ = std::make_unique<image_transport::ImageTransport>(nh);
  const image_transport::TransportHints hints(params_.image_transport, ros::TransportHints(), pnh);
  try {
    // Resolved first, so a transport plugin's "<base>/compressed" follows the
    // remapping of `image` (StereoFrontendNodelet::subscribeImages).
    sub_ = it_->subscribe(nh.resolveName("image"), 5, &ImagingFlowNodelet::onImage, this, hints);
  } catch (const std::exception& ex) {
    return startup_.refuse(getNodeHandle(), getPrivateNodeHandle(), getName(),
                           "image transport '" + params_.image_transport + "' unavailable", {ex.what()});
  }
  startDiagnostics();
  NODELET_INFO("imaging flow: pixel (%g, %g) (-1: image centre), search radius %d px, %d features, LK %d px x %d "
               "levels, backend %s; %s (transport '%s') -> %s",
               params_.flow.u, params_.flow.v, params_.flow.search_radius, params_.flow.max_features,
               params_.flow.lk_window, params_.flow.pyramid_levels, tracker_->backendStatus().c_str(),
               sub_.getTopic().c_str(),
               params_.image_transport.c_str(), pub_.getTopic().c_str());
}

void ImagingFlowNodelet::startDiagnostics() {
  updater_ = std::make_unique<diagnostic_updater::Updater>(getNodeHandle(), getPrivateNodeHandle(), getName());
  updater_->setHardwareID(kHardwareId);
  updater_->add(kStatusName, &diag_, &ImagingFlowDiagnostics::produce);
  // Wall timer: diagnostics keep flowing when simulated time pauses.
  diag_timer_ = getNodeHandle().createWallTimer(ros::WallDuration(std::max(0.1, updater_->getPeriod())),
                                                [this](const ros::WallTimerEvent&) { updater_->force_update(); });
}

void ImagingFlowNodelet::badImage(const std::string& reason, const std::string& detail) {
  diag_.badImage(reason, detail);
  if (error_log_.shouldLog(reason)) NODELET_ERROR("bad imaging frame [%s]: %s", reason.c_str(), detail.c_str());
}

void ImagingFlowNodelet::onImage(const sensor_msgs::ImageConstPtr& image) {
  diag_.frame();
  if (image->header.frame_id.empty()) return badImage("missing_frame_id", "the image has no frame_id");
  cv::Mat grey;
  if (const InputError e = convertToGrey(rawView(*image), params_.mono16_bits, &grey))
    return badImage(e.reason, e.detail);
  ImageFlowResult result;
  const auto start = std::chrono::steady_clock::now();
  InputError error;
  {
    std::lock_guard<std::mutex> lock(tracker_mutex_);
    try {
      error = tracker_->process(grey, static_cast<std::int64_t>(image->header.stamp.toNSec()), &result);
    } catch (const std::exception& ex) {
      // Last line of defence: a bug in the core must not take the manager
      // down; the tracker starts afresh.
      tracker_->reset();
      error = InputError{"internal_error", ex.what()};
    }
    // The CUDA tracker failed at run time; the CPU one took over (restart).
    if (result.restart_reason == "gpu_failed") {
      NODELET_ERROR("imaging flow: %s", tracker_->backendStatus().c_str());
      diag_.backend(tracker_->backendStatus());
    }
  }
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (error) {
    badImage(error.reason, error.detail);
    if (error.reason != "size_changed") return;  // the frame was ignored; a size change restarted
  }
  auto msg = boost::make_shared<hapi_msgs::ImageFlow>();
  fillFlowMsg(result, image->header, msg.get());
  pub_.publish(msg);  // shared pointer: zero-copy to nodelets in the same manager
  diag_.published(result, ms);
}

}  // namespace hapi_frontend

PLUGINLIB_EXPORT_CLASS(hapi_frontend::ImagingFlowNodelet, nodelet::Nodelet)
