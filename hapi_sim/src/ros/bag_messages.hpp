// hapi_sim ROS side: the message conversions and bag conventions both bag
// writers share (make_globe_bag and make_sim_bag): integer-nanosecond stamps
// from a fixed epoch, CameraInfo/Image/Transform/Odometry from the core's
// types, latched connection headers, the globe's info YAML and the tools'
// number parsing.
#pragma once
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/message_traits.h>
#include <ros/time.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <boost/make_shared.hpp>
#include <cstdint>
#include <string>

#include "hapi_sim/globe_sim.hpp"
#include "hapi_sim/motion.hpp"

namespace hapi_sim {

// Stamp of `ns` nanoseconds after the fixed epoch of 1e9 s (never wall time;
// integer arithmetic, no floating-point rounding).
ros::Time stampAt(int64_t ns);

sensor_msgs::CameraInfo toCameraInfoMsg(const CameraInfoData& d, const std_msgs::Header& h);
sensor_msgs::Image toImageMsg(const cv::Mat& mono8, const std_msgs::Header& h);
geometry_msgs::TransformStamped toTransformMsg(const ros::Time& t, const std::string& parent, const std::string& child,
                                               const Eigen::Vector3d& p, const Eigen::Quaterniond& q);
// nav_msgs/Odometry (REP-105): pose of child in frame_id, twist in child.
nav_msgs::Odometry toOdometryMsg(const ros::Time& t, const std::string& frame, const std::string& child,
                                 const MotionSample& m);

// The /globe/info YAML (radius, centre, frame, seed, texture source).
std::string globeInfoYaml(double radius, const Eigen::Vector3d& centre, const std::string& frame, uint32_t seed,
                          const std::string& texture);

// Number of a command-line option; throws std::invalid_argument with the
// message to print when it is not a finite number.
double parseNumberArg(const std::string& key, const std::string& value);

// Latched connections (tf_static, scene descriptions) need an explicit
// connection header so that `rosbag play` re-advertises them latched.
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

}  // namespace hapi_sim
