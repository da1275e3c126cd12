// The synchronised stereo input of the nodelets that take the raw pair
// (StereoFrontendNodelet, hapi_surface's DenseDepthNodelet): left/image_raw
// and right/image_raw through image_transport, left/camera_info and
// right/camera_info, matched by an exact or approximate stamp policy.
// Subscribing is split in two steps so that a missing transport plugin can
// refuse the nodelet before anything else starts; the callbacks run on the
// manager's threads.
#pragma once

#include <image_transport/image_transport.h>
#include <image_transport/subscriber_filter.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <functional>
#include <memory>
#include <string>

namespace hapi_frontend {

class StereoPairInput {
 public:
  using PairCallback =
      std::function<void(const sensor_msgs::ImageConstPtr& left, const sensor_msgs::CameraInfoConstPtr& left_info,
                         const sensor_msgs::ImageConstPtr& right, const sensor_msgs::CameraInfoConstPtr& right_info)>;

  ~StereoPairInput() { shutdown(); }

  // The two images through the image_transport plugin `transport` (the
  // hint reads ~image_transport of pnh). "" or why not (pluginlib throws
  // when the plugin is not installed; then nothing stays subscribed).
  std::string subscribeImages(ros::NodeHandle& nh, ros::NodeHandle& pnh, const std::string& transport, int queue);
  // The CameraInfo pair and the synchroniser: on_pair for every matched set;
  // with the exact policy on_drop (may be empty) for a set that found no
  // partner with the same stamp.
  void synchronise(ros::NodeHandle& nh, int queue, bool approximate, PairCallback on_pair, PairCallback on_drop);
  // Unsubscribes everything; waits for running callbacks.
  void shutdown();

  // "left left_info right right_info" as resolved, for the start-up log.
  std::string topics() const;

 private:
  using Image = sensor_msgs::Image;
  using Info = sensor_msgs::CameraInfo;
  using ExactPolicy = message_filters::sync_policies::ExactTime<Image, Info, Image, Info>;
  using ApproxPolicy = message_filters::sync_policies::ApproximateTime<Image, Info, Image, Info>;
  void onPair(const sensor_msgs::ImageConstPtr& l, const sensor_msgs::CameraInfoConstPtr& li,
              const sensor_msgs::ImageConstPtr& r, const sensor_msgs::CameraInfoConstPtr& ri);
  void onDrop(const sensor_msgs::ImageConstPtr& l, const sensor_msgs::CameraInfoConstPtr& li,
              const sensor_msgs::ImageConstPtr& r, const sensor_msgs::CameraInfoConstPtr& ri);

  PairCallback on_pair_, on_drop_;
  std::unique_ptr<image_transport::ImageTransport> it_;
  image_transport::SubscriberFilter left_sub_, right_sub_;
  message_filters::Subscriber<Info> left_info_sub_, right_info_sub_;
  std::unique_ptr<message_filters::Synchronizer<ExactPolicy>> exact_sync_;
  std::unique_ptr<message_filters::Synchronizer<ApproxPolicy>> approx_sync_;
};

}  // namespace hapi_frontend
