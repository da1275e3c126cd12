// Odometry, pose and TF outputs of EskfNodelet, per frame and at the IMU rate
// (output_publisher.hpp says which thread calls what).
#include "hapi_eskf/ros/output_publisher.hpp"

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/console.h>

#include <utility>

namespace hapi_eskf {
namespace ros_glue {

OutputPublisher::OutputPublisher(const NodeletParams& params, ros::Publisher odom_pub, ros::Publisher pose_pub,
                                 const ImuInput* imu, NodeletStatistics& stats, std::string log_name)
    : world_frame_(params.world_frame),
      base_frame_(params.base_frame),
      publish_tf_(params.publish_tf),
      imu_(imu),
      stats_(stats),
      log_name_(std::move(log_name)),
      odom_pub_(std::move(odom_pub)),
      pose_pub_(std::move(pose_pub)) {
  if (params.usesImu()) propagator_ = std::make_unique<PosePropagator>(params.filter);
}

void OutputPublisher::setMapAnchor(const Eigen::Isometry3d& T_map_world) {
  std::lock_guard<std::mutex> lk(mu_);
  T_map_world_ = T_map_world;
  T_cam_base_ = T_map_world.inverse();
}

void OutputPublisher::unanchorMap() {
  std::lock_guard<std::mutex> lk(mu_);
  T_map_world_ = Eigen::Isometry3d::Identity();
}

Eigen::Isometry3d OutputPublisher::mapFromWorld() const {
  std::lock_guard<std::mutex> lk(mu_);
  return T_map_world_;
}

CameraInMap OutputPublisher::publishFrame(const ros::Time& stamp, const std::string& camera_frame,
                                          const SlamBackend& filter, bool scene_moving) {
  std::lock_guard<std::mutex> lk(mu_);
  camera_frame_ = camera_frame;
  const PoseState pose = filter.pose();
  const CameraInMap T_map_cam = toCameraInMap(pose, T_map_world_);
  // With an IMU model the IMU-rate output may already be past this frame
  // (front-end latency): outputs keep strictly increasing stamps, and the
  // corrected state reaches the next ones through the re-based propagation.
  if (stamp > last_output_stamp_) publish(stamp, pose, filter.cameraCovariance(), T_map_cam);
  if (propagator_) {
    propagator_->rebase(filter, scene_moving);
    // Catch up with the samples already received after this frame (their
    // outputs are out already unless one arrived during this block).
    for (const TimedImuSample& s : imu_->samplesAfter(filter.time())) stepAndPublish(s);
  }
  return T_map_cam;
}

void OutputPublisher::restart() {
  std::lock_guard<std::mutex> lk(mu_);
  last_output_stamp_ = ros::Time();
  if (propagator_) propagator_->invalidate();
}

void OutputPublisher::publishImuRate(const TimedImuSample& s) {
  std::lock_guard<std::mutex> lk(mu_);
  stepAndPublish(s);
}

void OutputPublisher::stepAndPublish(const TimedImuSample& s) {
  const double t = s.sample.stamp;
  if (!propagator_ || !propagator_->valid() || t <= propagator_->time()) return;
  const Status st = propagator_->step(s.sample);
  if (st != Status::kOk) {
    ROS_WARN_THROTTLE_NAMED(2.0, log_name_, "IMU-rate propagation failed at %.3f: %s", t, toString(st));
    return;
  }
  if (!propagator_->publishable()) {
    ++stats_.counters.imu_outputs_held;
    return;
  }
  // One output per sample: the output rate is the IMU rate. Stamps are
  // compared as ros::Time: the sample's camera-clock stamp in seconds may
  // round one ulp above a frame's stamp it equals, and TF rejects a repeat.
  if (s.ros_stamp > last_output_stamp_) {
    const PoseState pose = propagator_->pose();
    publish(s.ros_stamp, pose, propagator_->cameraCovariance(), toCameraInMap(pose, T_map_world_));
    ++stats_.counters.imu_outputs;
  }
}

void OutputPublisher::publish(const ros::Time& stamp, const PoseState& pose, const Mat12& C,
                              const CameraInMap& T_map_cam) {
  last_output_stamp_ = stamp;
  ++stats_.counters.outputs;
  nav_msgs::Odometry odom;
  odom.header.stamp = stamp;
  odom.header.frame_id = world_frame_;
  odom.child_frame_id = camera_frame_;
  odom.pose = toPoseWithCovariance(T_map_cam, C, T_map_world_.linear());
  odom.twist = toTwistWithCovariance(pose, C);
  odom_pub_.publish(odom);

  geometry_msgs::PoseWithCovarianceStamped ps;
  ps.header = odom.header;
  ps.pose = odom.pose;
  pose_pub_.publish(ps);

  if (publish_tf_) {
    // One parent per frame in TF: the camera (or base) frame's parent becomes
    // world_frame. With ~base_frame, T_map_base = T_map_cam * T_cam_base.
    geometry_msgs::TransformStamped t;
    t.header = odom.header;
    if (base_frame_.empty()) {
      t.child_frame_id = camera_frame_;
      t.transform = toTransform(T_map_cam.isometry());
    } else {
      t.child_frame_id = base_frame_;
      t.transform = toTransform(T_map_cam.isometry() * T_cam_base_);
    }
    tf_broadcaster_.sendTransform(t);
  }
}

}  // namespace ros_glue
}  // namespace hapi_eskf
