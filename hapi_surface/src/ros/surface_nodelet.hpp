// hapi_surface/SurfaceNodelet: the 3D surface of the scanned skin with the
// imaging camera's frames projected on it (docs/DESIGN.md "Surface"), a
// thin wrapper of SurfaceMapper.
//
// In (relative to the nodelet's namespace, remapped by the launch file):
//   depth, depth_camera_info, depth_confidence (optional, ~use_confidence):
//                     the dense stereo depth (depth_image_contract.hpp)
//   imaging/image     sensor_msgs/Image of the imaging camera, any of
//                     floatEncodingsText() (32FC1: a perfusion map in its units)
//   imaging/camera_info  its CameraInfo
//   path              nav_msgs/Path of the filter (optional): a change of a
//                     past pose corrects the keyframes (rebuild)
//   odom              nav_msgs/Odometry of the filter (optional): its pose
//                     covariance for the settle rule (settle_gate.hpp)
//   TF                ~world_frame -> each image's frame at its stamp
// Out: ~mesh (visualization_msgs/Marker TRIANGLE_LIST, per-vertex colours of
//   the projected value, every ~mesh_period), service ~save_surface
//   (hapi_msgs/SaveSurface: PLY, or OBJ + MTL + PNG texture for a path
//   ending in .obj), /diagnostics ("surface").
// One mutex guards the mapper; the callbacks may run on several threads.
#pragma once

#include "surface_params.hpp"
#include "surface_statistics.hpp"

#include "hapi_surface/colour_map.hpp"
#include "hapi_surface/surface_mapper.hpp"

#include <diagnostic_updater/diagnostic_updater.h>
#include <hapi_msgs/SaveSurface.h>
#include <hapi_nodelet_kit/stamp_guard.hpp>
#include <hapi_nodelet_kit/startup_failure.hpp>
#include <message_filters/subscriber.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/message_filter.h>
#include <tf2_ros/transform_listener.h>

#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

namespace hapi_surface {

class CudaSurfaceVolume;

class SurfaceNodelet : public nodelet::Nodelet {
 public:
  ~SurfaceNodelet() override;

 private:
  using ImageFilter = tf2_ros::MessageFilter<sensor_msgs::Image>;
  void onInit() override;
  void depthCallback(const sensor_msgs::ImageConstPtr& msg);
  void confidenceCallback(const sensor_msgs::ImageConstPtr& msg);
  void imagingCallback(const sensor_msgs::ImageConstPtr& msg);
  void pathCallback(const nav_msgs::PathConstPtr& msg);
  void odomCallback(const nav_msgs::OdometryConstPtr& msg);
  // The mapper's keyframe counters into stats_ (under mu_).
  void countKeyframes();
  // The odometry's uncertainties received since the last call, into the mapper (under mu_).
  void takeOdometry();
  void publishMesh();
  bool saveService(hapi_msgs::SaveSurface::Request& req, hapi_msgs::SaveSurface::Response& res);
  // ~world_frame -> frame at stamp (TF has it: the message filters waited).
  std::optional<Eigen::Isometry3d> poseAt(const std::string& frame, const ros::Time& stamp) const;
  // The confidence image of `stamp` (under mu_), empty if none.
  FloatImage confidenceAt(const ros::Time& stamp);
  // Display colours of the mesh's values.
  std::vector<Rgb8> colours(const Mesh& mesh) const;
  // A new, empty surface with the configured integrator (under mu_ once
  // running).
  void resetMapper();
  // Subscribes `topic` through a TF message filter to ~world_frame.
  void subscribeWithTf(const std::string& topic, message_filters::Subscriber<sensor_msgs::Image>* sub,
                       std::unique_ptr<ImageFilter>* filter, void (SurfaceNodelet::*cb)(const sensor_msgs::ImageConstPtr&),
                       ros_glue::SurfaceStatistics::Counter* no_tf);

  ros_glue::SurfaceParams params_;
  static constexpr const char* kStatusName = "surface";
  static constexpr const char* kHardwareId = "hapi_surface";
  hapi_nodelet_kit::StartupFailure startup_{kStatusName, kHardwareId};
  ros_glue::SurfaceStatistics stats_;

  std::mutex mu_;
  std::unique_ptr<SurfaceMapper> mapper_;
  std::unique_ptr<hapi_nodelet_kit::StampGuard> depth_guard_;
  // The volume's device copy, used by the mapper's integrator and mesher
  // (under mu_): each uploads the mapper's host volume, so the two stay one.
  std::unique_ptr<CudaSurfaceVolume> cuda_;
  std::optional<PinholeCamera> depth_camera_, imaging_camera_;
  std::deque<sensor_msgs::ImageConstPtr> confidence_;
  std::map<std::uint64_t, Eigen::Isometry3d> last_path_;  // stamp (ns) -> pose
  std::mutex odom_mu_;                 // guards odom_ only
  std::vector<PoseUncertainty> odom_;  // received, not yet in the mapper
  ros::Time last_projection_;

  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  message_filters::Subscriber<sensor_msgs::Image> depth_sub_, imaging_sub_;
  std::unique_ptr<ImageFilter> depth_filter_, imaging_filter_;
  ros::Subscriber depth_info_sub_, imaging_info_sub_, confidence_sub_, path_sub_, odom_sub_;
  ros::Publisher mesh_pub_;
  ros::ServiceServer save_srv_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  ros::WallTimer diag_timer_, mesh_timer_;
};

}  // namespace hapi_surface
