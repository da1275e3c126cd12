// Messages shared by the recording tools (see bag_messages.hpp).
#include "hapi_dataset/ros/bag_messages.hpp"

#include <tf2_eigen/tf2_eigen.h>

#include <algorithm>
#include <stdexcept>

namespace hapi_dataset {

sensor_msgs::CameraInfo toCameraInfoMsg(const CameraInfoData& d, const std_msgs::Header& h) {
  sensor_msgs::CameraInfo m;
  m.header = h;
  m.width = d.width;
  m.height = d.height;
  m.distortion_model = d.distortion_model;
  m.D = d.D;
  std::copy(d.K.begin(), d.K.end(), m.K.begin());
  std::copy(d.R.begin(), d.R.end(), m.R.begin());
  std::copy(d.P.begin(), d.P.end(), m.P.begin());
  return m;
}

sensor_msgs::Image toImageMsg(const cv::Mat& image, const std_msgs::Header& h) {
  if (image.type() != CV_8UC1 && image.type() != CV_32FC1)
    throw std::invalid_argument("toImageMsg: the image must be CV_8UC1 or CV_32FC1");
  sensor_msgs::Image m;
  m.header = h;
  m.height = image.rows;
  m.width = image.cols;
  m.encoding = image.type() == CV_8UC1 ? "mono8" : "32FC1";
  m.is_bigendian = 0;
  m.step = static_cast<uint32_t>(image.cols * image.elemSize());
  m.data.resize(static_cast<size_t>(m.step) * image.rows);
  for (int r = 0; r < image.rows; ++r)
    std::copy(image.ptr<uint8_t>(r), image.ptr<uint8_t>(r) + m.step, m.data.begin() + static_cast<size_t>(r) * m.step);
  return m;
}

geometry_msgs::TransformStamped toTransformMsg(const ros::Time& t, const std::string& parent, const std::string& child,
                                               const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  geometry_msgs::TransformStamped tf;
  tf.header.stamp = t;
  tf.header.frame_id = parent;
  tf.child_frame_id = child;
  tf2::toMsg(p, tf.transform.translation);
  tf.transform.rotation = tf2::toMsg(q);
  return tf;
}

geometry_msgs::Pose toPoseMsg(const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  geometry_msgs::Pose m;
  m.position = tf2::toMsg(p);
  m.orientation = tf2::toMsg(q);
  return m;
}

sensor_msgs::Imu toImuMsg(const ros::Time& t, const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel,
                          double gyro_variance, double accel_variance) {
  sensor_msgs::Imu m;
  m.header.stamp = t;
  m.header.frame_id = recording_frames::kImu;
  m.orientation_covariance[0] = -1.0;
  tf2::toMsg(gyro, m.angular_velocity);
  tf2::toMsg(accel, m.linear_acceleration);
  for (int k = 0; k < 3; ++k) {
    m.angular_velocity_covariance[4 * k] = gyro_variance;
    m.linear_acceleration_covariance[4 * k] = accel_variance;
  }
  return m;
}

}  // namespace hapi_dataset
