// StereoPairInput (stereo_pair_input.hpp).
#include "stereo_pair_input.hpp"

namespace hapi_frontend {

std::string StereoPairInput::subscribeImages(ros::NodeHandle& nh, ros::NodeHandle& pnh, const std::string& transport,
                                             int queue) {
  const uint32_t q = static_cast<uint32_t>(queue);
  it_ = std::make_unique<image_transport::ImageTransport>(nh);
  // The hint reads ~image_transport (already validated), so "compressed"
  // subscribes to <image>/compressed through the plugin.
  const image_transport::TransportHints hints(transport, ros::TransportHints(), pnh);
  try {
    // Resolve (and so remap) the base topics here: a transport plugin
    // subscribes to "<base>/compressed", a name the nodelet's remapping of
    // left/image_raw does not match, so with an unresolved base the compressed
    // front end listened on /left/image_raw/compressed whatever the launch file
    // remapped (frontend_inputs.test caught it).
    left_sub_.subscribe(*it_, nh.resolveName("left/image_raw"), q, hints);
    right_sub_.subscribe(*it_, nh.resolveName("right/image_raw"), q, hints);
  } catch (const std::exception& ex) {
    // pluginlib throws when the transport plugin is not installed (Debian
    // ships only "raw"; "compressed" needs compressed_image_transport).
    left_sub_.unsubscribe();
    right_sub_.unsubscribe();
    return ex.what();
  }
  return "";
}

void StereoPairInput::synchronise(ros::NodeHandle& nh, int queue, bool approximate, PairCallback on_pair,
                                  PairCallback on_drop) {
  on_pair_ = std::move(on_pair);
  on_drop_ = std::move(on_drop);
  const uint32_t q = static_cast<uint32_t>(queue);
  left_info_sub_.subscribe(nh, "left/camera_info", q);
  right_info_sub_.subscribe(nh, "right/camera_info", q);
  if (approximate) {
    // No max-interval limit in the policy: pairs beyond a user's slop reach
    // the callback, which can count and log them.
    approx_sync_ = std::make_unique<message_filters::Synchronizer<ApproxPolicy>>(
        ApproxPolicy(q), left_sub_, left_info_sub_, right_sub_, right_info_sub_);
    approx_sync_->registerCallback(&StereoPairInput::onPair, this);
  } else {
    exact_sync_ = std::make_unique<message_filters::Synchronizer<ExactPolicy>>(
        ExactPolicy(q), left_sub_, left_info_sub_, right_sub_, right_info_sub_);
    exact_sync_->registerCallback(&StereoPairInput::onPair, this);
    exact_sync_->registerDropCallback(&StereoPairInput::onDrop, this);
  }
}

void StereoPairInput::shutdown() {
  left_sub_.unsubscribe();
  right_sub_.unsubscribe();
  left_info_sub_.unsubscribe();
  right_info_sub_.unsubscribe();
}

std::string StereoPairInput::topics() const {
  return left_sub_.getTopic() + " " + left_info_sub_.getTopic() + " " + right_sub_.getTopic() + " " +
         right_info_sub_.getTopic();
}

void StereoPairInput::onPair(const sensor_msgs::ImageConstPtr& l, const sensor_msgs::CameraInfoConstPtr& li,
                             const sensor_msgs::ImageConstPtr& r, const sensor_msgs::CameraInfoConstPtr& ri) {
  on_pair_(l, li, r, ri);
}

void StereoPairInput::onDrop(const sensor_msgs::ImageConstPtr& l, const sensor_msgs::CameraInfoConstPtr& li,
                             const sensor_msgs::ImageConstPtr& r, const sensor_msgs::CameraInfoConstPtr& ri) {
  if (on_drop_) on_drop_(l, li, r, ri);
}

}  // namespace hapi_frontend
