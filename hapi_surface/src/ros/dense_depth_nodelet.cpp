// DenseDepthNodelet (dense_depth_nodelet.hpp): start-up, the synchronised
// callback and the worker.
#include "dense_depth_nodelet.hpp"

#include <pluginlib/class_list_macros.hpp>

#include <chrono>
#include <functional>

namespace hapi_surface {

DenseDepthNodelet::~DenseDepthNodelet() {
  // Inputs first: unsubscribing waits for running callbacks, so none can
  // touch the mailbox while the members below are destroyed.
  diag_timer_.stop();
  input_.shutdown();
  mailbox_.close();
  if (worker_.joinable()) worker_.join();
}

void DenseDepthNodelet::onInit() {
  ros::NodeHandle& nh = getMTNodeHandle();
  ros::NodeHandle& pnh = getMTPrivateNodeHandle();
  hapi_nodelet_kit::ParamReader reader(pnh);
  readDenseDepthParams(reader, &params_);
  for (const auto& w : reader.warnings()) NODELET_WARN("%s", w.c_str());
  if (!reader.ok())
    return startup_.refuse(getNodeHandle(), getPrivateNodeHandle(), getName(), "invalid parameters",
                           reader.errors());
  processor_ = std::make_unique<DenseDepthProcessor>(params_);  // parameters validated above
  gate_ = std::make_unique<DenseDepthKeyframeGate>(params_.rate);
  const std::string why = input_.subscribeImages(nh, pnh, params_.image_transport, params_.queue_size);
  if (!why.empty())
    return startup_.refuse(getNodeHandle(), getPrivateNodeHandle(), getName(),
                           "image transport '" + params_.image_transport + "' unavailable", {why});
  startDiagnostics();
  depth_pub_ = pnh.advertise<sensor_msgs::Image>("depth", 2);
  confidence_pub_ = pnh.advertise<sensor_msgs::Image>("confidence", 2);
  info_pub_ = pnh.advertise<sensor_msgs::CameraInfo>("camera_info", 2);
  worker_ = std::thread(&DenseDepthNodelet::workerLoop, this);

  using namespace std::placeholders;
  input_.synchronise(nh, params_.queue_size, params_.approximate_sync,
                     std::bind(&DenseDepthNodelet::onSynced, this, _1, _2, _3, _4), nullptr);
  NODELET_INFO("dense depth: %.2f Hz, depth %.2f-%.2f m, image scale %.3g, block %d, left-right check %s; "
               "%s -> %s %s",
               params_.rate, params_.depth.min_depth, params_.depth.max_depth, params_.depth.image_scale,
               params_.depth.block_size, params_.depth.left_right_check ? "on" : "off", input_.topics().c_str(),
               depth_pub_.getTopic().c_str(), confidence_pub_.getTopic().c_str());
}

void DenseDepthNodelet::startDiagnostics() {
  updater_ = std::make_unique<diagnostic_updater::Updater>(getNodeHandle(), getPrivateNodeHandle(), getName());
  updater_->setHardwareID(kHardwareId);
  updater_->add(kStatusName, &diag_, &DenseDepthDiagnostics::produce);
  // Wall timer: diagnostics keep flowing when simulated time pauses.
  diag_timer_ = getNodeHandle().createWallTimer(ros::WallDuration(std::max(0.1, updater_->getPeriod())),
                                                [this](const ros::WallTimerEvent&) { updater_->force_update(); });
}

void DenseDepthNodelet::reject(const std::string& reason, const std::string& detail) {
  diag_.rejected(reason, detail);
  if (error_log_.shouldLog(reason)) NODELET_ERROR("rejected stereo pair [%s]: %s", reason.c_str(), detail.c_str());
}

void DenseDepthNodelet::onSynced(const sensor_msgs::ImageConstPtr& l, const sensor_msgs::CameraInfoConstPtr& li,
                                 const sensor_msgs::ImageConstPtr& r, const sensor_msgs::CameraInfoConstPtr& ri) {
  diag_.pair();
  // roscpp runs one synchroniser's callback at a time: the gate needs no lock.
  if (!gate_->take(static_cast<std::int64_t>(l->header.stamp.toNSec()))) return;
  diag_.keyframe();
  if (mailbox_.put(Pair{l, r, li, ri})) diag_.dropped("busy");  // the worker is behind: newest pair wins
}

void DenseDepthNodelet::workerLoop() {
  while (std::optional<Pair> pair = mailbox_.take()) {  // empty once closed
    try {
      processPair(*pair);
    } catch (const std::exception& ex) {
      // Last line of defence: a bug in the core must not take the manager down.
      reject("internal_error", ex.what());
    }
  }
}

void DenseDepthNodelet::processPair(const Pair& p) {
  const auto start = std::chrono::steady_clock::now();
  DepthMessages out;
  if (const InputError e = processor_->process(p.left, p.left_info, p.right, p.right_info, &out))
    return reject(e.reason, e.detail);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  // Shared pointers: zero-copy to nodelets in the same manager.
  depth_pub_.publish(out.depth);
  confidence_pub_.publish(out.confidence);
  info_pub_.publish(out.camera_info);
  diag_.published(ms, out.valid_fraction);
}

}  // namespace hapi_surface

PLUGINLIB_EXPORT_CLASS(hapi_surface::DenseDepthNodelet, nodelet::Nodelet)
