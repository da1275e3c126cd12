// image_transport "compressed" subscriber plugin (sensor_msgs/CompressedImage,
// JPEG or PNG, on <base topic>/compressed) for the front end.
//
// Why our own: a camera driver on the robot publishes compressed images through
// image_transport, and Debian packages only the "raw" transport (no
// compressed_image_transport). The plugin registers the standard lookup name
// image_transport/compressed_sub, so ~image_transport: compressed works as on
// any ROS install; where the upstream plugin is also installed, pluginlib
// keeps the first class of that name it finds and either decodes the same
// messages.
#pragma once

#include <image_transport/simple_subscriber_plugin.h>
#include <ros/time.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>

#include <string>

namespace hapi_frontend {

// CompressedImage -> Image. The output encoding is the one named before ';'
// in `format` ("rgb8; jpeg compressed bgr8" -> rgb8, as the upstream
// publisher writes it) when it is mono8/mono16/bgr8/rgb8; otherwise it follows
// the decoded data (1 channel: mono8/mono16, 3: bgr8, 4: bgra8, which the
// front end rejects and counts). Undecodable data gives a 0x0 image with the
// header kept, so the front end counts the pair as malformed instead of the
// transport dropping it silently. Returns false (and *error) in that case.
// Only PNG and JPEG are decoded (what the compressed transport sends), and
// only up to kMaxDecodedImageBytes as their header announces
// (image_header.hpp), checked before anything is allocated.
bool decodeCompressed(const sensor_msgs::CompressedImage& in, sensor_msgs::Image* out, std::string* error);

class CompressedSubscriber : public image_transport::SimpleSubscriberPlugin<sensor_msgs::CompressedImage> {
 public:
  std::string getTransportName() const override { return "compressed"; }

 protected:
  void internalCallback(const sensor_msgs::CompressedImageConstPtr& message, const Callback& user_cb) override;

 private:
  // When this subscriber last logged a decode error (at most once per
  // second). Per instance, not ROS_ERROR_THROTTLE's static per call site:
  // the left and right subscribers run their callbacks on different
  // threads and would race on that static; one subscription's callbacks
  // never run concurrently, so this member needs no lock.
  ros::WallTime last_error_log_;
};

}  // namespace hapi_frontend
