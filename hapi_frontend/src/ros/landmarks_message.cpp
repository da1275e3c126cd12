#include "landmarks_message.hpp"

#include <tf2_eigen/tf2_eigen.h>

#include <cstring>

namespace hapi_frontend {

std::string fillLandmarksMsg(const StereoFrameResult& res, const std_msgs::Header& header,
                             hapi_msgs::StereoLandmarks* msg) {
  const std::string problem = publishProblem(res);
  if (!problem.empty()) return problem;
  const size_t n = res.landmarks.size();
  const cv::Mat& d = res.descriptors;

  msg->header = header;
  msg->descriptor_type = res.descriptor_type == DescriptorType::AKAZE ? hapi_msgs::StereoLandmarks::DESCRIPTOR_AKAZE
                                                                      : hapi_msgs::StereoLandmarks::DESCRIPTOR_ORB;
  msg->descriptor_length = n > 0 ? static_cast<uint32_t>(d.cols) : (res.descriptor_type == DescriptorType::AKAZE ? 61u : 32u);
  msg->descriptors.resize(n * msg->descriptor_length);
  for (size_t i = 0; i < n; ++i)
    std::memcpy(&msg->descriptors[i * msg->descriptor_length], d.ptr<uint8_t>(static_cast<int>(i)), msg->descriptor_length);

  msg->landmarks.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const StereoLandmarkOut& in = res.landmarks[i];
    hapi_msgs::StereoLandmark& o = msg->landmarks[i];
    o.id = static_cast<uint32_t>(i);
    o.position = tf2::toMsg(in.position);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) o.position_covariance[3 * r + c] = in.covariance(r, c);
    o.response = in.response;
    o.r = in.rgb[0];
    o.g = in.rgb[1];
    o.b = in.rgb[2];
  }
  return "";
}

}  // namespace hapi_frontend
