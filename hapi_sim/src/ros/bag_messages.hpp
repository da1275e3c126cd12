// hapi_sim ROS side: what both simulator bag writers (make_globe_bag and
// make_sim_bag) write beyond the messages every recording tool shares
// (hapi_dataset/ros/bag_messages.hpp, command_line.hpp): integer-nanosecond
// stamps from a fixed epoch, ground-truth odometry from the core's motion
// samples, the surface-motion truth and the globe's info YAML.
#pragma once
#include <hapi_msgs/SurfaceMotion.h>
#include <nav_msgs/Odometry.h>
#include <ros/time.h>

#include <cstdint>
#include <string>

#include "hapi_dataset/command_line.hpp"
#include "hapi_dataset/ros/bag_messages.hpp"

#include "hapi_sim/globe_sim.hpp"
#include "hapi_sim/motion.hpp"
#include "hapi_sim/surface_motion_truth.hpp"

namespace hapi_sim {

// Stamp of `ns` nanoseconds after the fixed epoch of 1e9 s (never wall time;
// integer arithmetic, no floating-point rounding).
ros::Time stampAt(int64_t ns);

using hapi_dataset::latchedHeader;
using hapi_dataset::parseNumberArg;
using hapi_dataset::toCameraInfoMsg;
using hapi_dataset::toImageMsg;
using hapi_dataset::toPoseMsg;
using hapi_dataset::toTransformMsg;

// nav_msgs/Odometry (REP-105): pose of child in frame_id, twist in child.
nav_msgs::Odometry toOdometryMsg(const ros::Time& t, const std::string& frame, const std::string& child,
                                 const MotionSample& m);

// hapi_msgs/SurfaceMotion of the truth in `frame` (the imaging optical
// frame): covariances zero (exact), flow_fused false.
hapi_msgs::SurfaceMotion toSurfaceMotionMsg(const ros::Time& t, const std::string& frame, const SurfaceMotionTruth& m);

// The /globe/info YAML (radius, centre, frame, seed, texture source).
std::string globeInfoYaml(double radius, const Eigen::Vector3d& centre, const std::string& frame, uint32_t seed,
                          const std::string& texture);

}  // namespace hapi_sim
