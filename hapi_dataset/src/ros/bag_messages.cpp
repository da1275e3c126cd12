// Messages shared by the recording tools (see bag_messages.hpp).
#include "hapi_dataset/ros/bag_messages.hpp"

#include <tf2_eigen/tf2_eigen.h>

#include <algorithm>

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

sensor_msgs::Image toImageMsg(const cv::Mat& mono, const std_msgs::Header& h) {
  sensor_msgs::Image m;
  m.header = h;
  m.height = mono.rows;
  m.width = mono.cols;
  m.encoding = "mono8";
  m.is_bigendian = 0;
  m.step = mono.cols;
  m.data.resize(static_cast<size_t>(mono.rows) * mono.cols);
  for (int r = 0; r < mono.rows; ++r)
    std::copy(mono.ptr<uint8_t>(r), mono.ptr<uint8_t>(r) + mono.cols, m.data.begin() + static_cast<size_t>(r) * mono.cols);
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
