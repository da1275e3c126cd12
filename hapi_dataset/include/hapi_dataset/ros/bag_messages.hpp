// The ROS messages every recording tool writes the same way (asl_to_bag here,
// hapi_sim's make_sim_bag and make_globe_bag): CameraInfo from the plain
// calibration type, mono8 images, transforms and poses (tf2_eigen's
// conversions), and the connection header that makes `rosbag play`
// re-advertise a topic latched.
#pragma once

#include <geometry_msgs/Pose.h>
#include <geometry_msgs/TransformStamped.h>
#include <ros/message_traits.h>
#include <ros/time.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>

#include <Eigen/Geometry>
#include <boost/make_shared.hpp>
#include <opencv2/core.hpp>

#include <string>

#include "hapi_dataset/camera_info.hpp"

namespace hapi_dataset {

// The TF frames every recording tool writes (REP-103 optical frames; the
// ground truth in a tree of its own, so it never fights the estimate's TF).
namespace recording_frames {
constexpr const char* kWorld = "world";
constexpr const char* kLeft = "stereo_left_optical_frame";
constexpr const char* kRight = "stereo_right_optical_frame";
constexpr const char* kImu = "imu_link";
constexpr const char* kGt = "ground_truth/stereo_left_optical_frame";
}  // namespace recording_frames

sensor_msgs::CameraInfo toCameraInfoMsg(const CameraInfoData& d, const std_msgs::Header& h);
// A CV_8UC1 image as mono8, a CV_32FC1 one as 32FC1 (a depth image, the
// simulator's perfusion pattern); other types throw std::invalid_argument.
sensor_msgs::Image toImageMsg(const cv::Mat& image, const std_msgs::Header& h);
geometry_msgs::TransformStamped toTransformMsg(const ros::Time& t, const std::string& parent, const std::string& child,
                                               const Eigen::Vector3d& p, const Eigen::Quaterniond& q);
// Position and quaternion as they are (tf2::toMsg of an Isometry3d would go
// through the rotation matrix and flip the sign to w >= 0).
geometry_msgs::Pose toPoseMsg(const Eigen::Vector3d& p, const Eigen::Quaterniond& q);
// An IMU sample in frame kImu: no orientation (REP-145: covariance[0] = -1),
// the white-noise variance of each axis on the diagonals (0: unknown).
sensor_msgs::Imu toImuMsg(const ros::Time& t, const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel,
                          double gyro_variance, double accel_variance);

// Latched connections (tf_static, calibration and scene descriptions) need an
// explicit connection header so that `rosbag play` re-advertises them latched.
template <class M>
boost::shared_ptr<ros::M_string> latchedHeader(const std::string& callerid) {
  auto h = boost::make_shared<ros::M_string>();
  (*h)["type"] = ros::message_traits::datatype<M>();
  (*h)["md5sum"] = ros::message_traits::md5sum<M>();
  (*h)["message_definition"] = ros::message_traits::definition<M>();
  (*h)["callerid"] = callerid;
  (*h)["latching"] = "1";
  return h;
}

}  // namespace hapi_dataset
