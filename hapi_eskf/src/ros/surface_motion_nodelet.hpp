// hapi_eskf/SurfaceMotionNodelet: the skin's motion at a pixel of the imaging
// camera (docs/DESIGN.md "Surface motion"), a thin wrapper of
// surface_motion::SurfaceMotionEstimator.
//
// In (relative to the nodelet's namespace, remapped by the launch file):
//   odom                  nav_msgs/Odometry, the ESKF's IMU-rate output (pose of
//                         the child frame in the world, twist in the child frame)
//   map                   sensor_msgs/PointCloud2, the landmarks (world frame)
//   flow                  hapi_msgs/ImageFlow of the imaging camera
//   imaging/camera_info   sensor_msgs/CameraInfo of the imaging camera
//   TF                    the odometry's child frame -> ~imaging_frame (static)
// Out: ~surface_motion (hapi_msgs/SurfaceMotion, one per odometry message),
//   ~surface_motion_marker (visualization_msgs/Marker), service
//   ~smoothed_motion (hapi_msgs/GetSurfaceMotion), /diagnostics.
// Callbacks may run on several threads: one mutex guards the estimator.
#pragma once

#include "surface_motion_params.hpp"
#include "surface_motion_statistics.hpp"

#include <diagnostic_updater/diagnostic_updater.h>
#include <hapi_msgs/GetSurfaceMotion.h>
#include <hapi_msgs/ImageFlow.h>
#include <hapi_nodelet_kit/stamp_guard.hpp>
#include <hapi_nodelet_kit/startup_failure.hpp>
#include <nav_msgs/Odometry.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <memory>
#include <mutex>
#include <optional>
#include <string>

namespace hapi_eskf {

class SurfaceMotionNodelet : public nodelet::Nodelet {
 public:
  ~SurfaceMotionNodelet() override;

 private:
  void onInit() override;
  void odomCallback(const nav_msgs::OdometryConstPtr& msg);
  void mapCallback(const sensor_msgs::PointCloud2ConstPtr& msg);
  void flowCallback(const hapi_msgs::ImageFlowConstPtr& msg);
  void cameraInfoCallback(const sensor_msgs::CameraInfoConstPtr& msg);
  bool smoothedService(hapi_msgs::GetSurfaceMotion::Request& req, hapi_msgs::GetSurfaceMotion::Response& res);
  // The imaging camera in the odometry's child frame (TF, cached once found);
  // "" when known, else why not. Under mu_.
  std::string extrinsic(const std::string& child_frame, Eigen::Isometry3d* T);
  // Publishes one output and its marker (counted). Under mu_.
  void publish(const surface_motion::SurfaceMotionOutput& out, const ros::Time& stamp);

  ros_glue::SurfaceMotionParams params_;
  static constexpr const char* kStatusName = "surface motion";
  static constexpr const char* kHardwareId = "hapi_surface_motion";
  // Reports a start-up failure (then nothing else is started).
  hapi_nodelet_kit::StartupFailure startup_{kStatusName, kHardwareId};
  ros_glue::SurfaceMotionStatistics stats_;

  std::mutex mu_;
  std::unique_ptr<surface_motion::SurfaceMotionEstimator> estimator_;
  std::unique_ptr<hapi_nodelet_kit::StampGuard> odom_guard_;
  std::string imaging_frame_, world_frame_, map_frame_;
  std::optional<Eigen::Isometry3d> T_child_imaging_;
  std::string extrinsic_child_;  // the child frame T_child_imaging_ was found for

  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  ros::Subscriber odom_sub_, map_sub_, flow_sub_, info_sub_;
  ros::Publisher motion_pub_, marker_pub_;
  ros::ServiceServer smoothed_srv_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  ros::WallTimer diag_timer_;
};

}  // namespace hapi_eskf
