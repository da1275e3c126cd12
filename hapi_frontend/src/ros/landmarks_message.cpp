#include "landmarks_message.hpp"

#include <cmath>
#include <cstring>

namespace hapi_frontend {

std::string fillLandmarksMsg(const StereoFrameResult& res, const StereoRig& rig, double pixel_sigma,
                             const std_msgs::Header& header, const sensor_msgs::CameraInfo& left_info,
                             const sensor_msgs::CameraInfo& right_info, hapi_msgs::StereoLandmarks* msg) {
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
    o.u_left = in.uv_left.x();
    o.v_left = in.uv_left.y();
    o.u_right = in.uv_right.x();
    o.v_right = in.uv_right.y();
    o.position.x = in.position.x();
    o.position.y = in.position.y();
    o.position.z = in.position.z();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) o.position_covariance[3 * r + c] = in.covariance(r, c);
    o.response = in.response;
    o.r = in.rgb[0];
    o.g = in.rgb[1];
    o.b = in.rgb[2];
  }

  msg->left_info = left_info;
  msg->right_info = right_info;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) msg->R_left_right[3 * r + c] = rig.R_lr(r, c);
    msg->t_left_right[r] = rig.t_lr(r);
  }
  msg->pixel_sigma = pixel_sigma;
  return "";
}

}  // namespace hapi_frontend
