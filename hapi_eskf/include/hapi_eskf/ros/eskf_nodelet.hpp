// hapi_eskf/EskfNodelet: thin ROS wrapper of hapi_eskf::Eskf.
//
// Threads: ROS callbacks only validate and convert (O(N), no filter access);
// they post the frame into a newest-wins Mailbox. One worker thread owns the
// filter (all Eskf calls, so GPU work never blocks a callback), publishes
// odom/pose/path/TF per frame and refreshes the map snapshot that a wall
// timer publishes at ~map_publish_rate. With ~use_imu the IMU callback
// publishes odom/pose/TF once per gyro sample from a propagated copy of the
// pose (pose_propagator.hpp, a 12x12 step, never the filter): outputs at the
// IMU rate that keep flowing while the worker is busy with a frame.
//
// Resets (service ~reset, or a stamp jumping backwards by more than
// ~time_jump_reset) bump an epoch; frames carry the epoch they were accepted
// in, and the worker resets the filter when it sees a newer epoch, so a frame
// of the old timeline can never reach the fresh filter.
#pragma once

#include "hapi_eskf/eskf.hpp"
#include "hapi_eskf/ros/export.hpp"
#include "hapi_eskf/ros/mailbox.hpp"
#include "hapi_eskf/ros/params.hpp"
#include "hapi_eskf/ros/pose_propagator.hpp"
#include "hapi_eskf/ros/validation.hpp"

#include <diagnostic_updater/diagnostic_updater.h>
#include <hapi_msgs/StereoLandmarks.h>
#include <nav_msgs/Odometry.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <array>
#include <atomic>
#include <condition_variable>
#include <optional>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

namespace hapi_eskf {

class EskfNodelet : public nodelet::Nodelet {
 public:
  EskfNodelet() = default;
  ~EskfNodelet() override;

 private:
  struct Work {
    StereoFrame frame;
    std::string frame_id;
    ros::Time stamp;  // the message's own stamp: outputs carry it exactly (no double round trip)
    std::uint64_t epoch = 0;
  };
  struct ImuSample {
    double stamp;
    ros::Time ros_stamp;  // exact, for the output header
    Vec3 gyro_camera;
  };
  // Sums of the per-stage timings since the last diagnostics report.
  struct StageStats {
    int n = 0;
    IterationReport sum;
    IterationReport last;
  };

  void onInit() override;
  void landmarksCallback(const hapi_msgs::StereoLandmarks::ConstPtr& msg);
  void imuCallback(const sensor_msgs::Imu::ConstPtr& msg);
  bool resetService(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  bool saveMapService(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  bool saveTrajectoryService(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  void mapTimer(const ros::WallTimerEvent&);
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);

  // --- worker thread only ---
  void workerLoop();
  void resetFilter();
  bool ensureFilter(const Work& w);
  bool anchorWorld(const Work& w);
  void applyImu(double up_to);
  bool process(Work& w);  // false: frame not used (error counted)
  // --- under out_mu_ (worker and IMU callback) ---
  void stepAndPublish(const ImuSample& s);  // one gyro step of the output copy + its output (~use_imu)
  nav_msgs::Odometry makeOdometry(const ros::Time& stamp, const PoseState& pose, const Mat12& C) const;
  void publishOutput(const nav_msgs::Odometry& odom);  // odom, pose, TF
  void recordPath(const nav_msgs::Odometry& odom);     // trajectory (TUM) + path, per frame
  void takeSnapshot();

  void reject(ros_glue::Reject r, const std::string& detail);
  bool waitForSnapshot(std::uint64_t after, std::shared_ptr<const std::vector<ros_glue::MapPoint>>* out);

  ros_glue::NodeletParams params_;
  ros::Subscriber landmarks_sub_, imu_sub_;
  ros::Publisher odom_pub_, pose_pub_, path_pub_, map_pub_;
  ros::ServiceServer reset_srv_, save_map_srv_, save_traj_srv_;
  ros::WallTimer map_timer_, diag_timer_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> tf_broadcaster_;

  // Callback-side state (landmarks callback, IMU callback).
  std::mutex input_mu_;
  ros_glue::ValidationConfig validation_;
  std::unique_ptr<ros_glue::StampGuard> stamp_guard_;
  std::string camera_frame_;  // locked by ~camera_frame or the first accepted message
  std::map<std::string, Eigen::Quaterniond> imu_to_camera_;  // cached static rotations
  double last_imu_stamp_ = -1.0;

  ros_glue::Mailbox<Work> mailbox_;
  std::atomic<std::uint64_t> epoch_{0};          // bumped by every reset request
  std::atomic<std::uint64_t> worker_epoch_{0};   // the epoch the filter runs in
  std::thread worker_;
  std::atomic<bool> stop_{false};

  std::mutex imu_mu_;
  std::deque<ImuSample> imu_buffer_;

  // Worker-owned filter state.
  std::unique_ptr<Eskf> eskf_;
  bool need_init_ = true;
  bool world_anchored_ = false;
  ros::Time last_stamp_;

  // Outputs (odom, pose, TF), published by the worker per frame and, with
  // ~use_imu, by the IMU callback per gyro sample, always with strictly
  // increasing stamps. out_mu_ guards everything below (the anchoring
  // transforms are written by the worker only, read by both).
  std::mutex out_mu_;
  Eigen::Isometry3d T_map_world_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_cam_base_ = Eigen::Isometry3d::Identity();
  std::string output_frame_;  // camera frame of the last processed frame
  // ~use_imu: copy of the pose re-based on the filter after every frame and
  // stepped by every newer gyro sample (pose_propagator.hpp).
  std::unique_ptr<ros_glue::PosePropagator> propagator_;
  double last_output_stamp_ = -1.0;

  // Shared outputs.
  std::mutex path_mu_;
  std::deque<ros_glue::StampedPose> trajectory_;  // in world_frame, bounded by path_max_length

  std::mutex snapshot_mu_;
  std::condition_variable snapshot_cv_;
  std::shared_ptr<const std::vector<ros_glue::MapPoint>> snapshot_;
  ros::Time snapshot_stamp_;
  std::uint64_t snapshot_generation_ = 0, published_generation_ = 0;
  std::atomic<bool> snapshot_requested_{false};
  ros::WallTime last_snapshot_wall_;

  // Counters for /diagnostics.
  std::atomic<std::uint64_t> n_received_{0}, n_accepted_{0}, n_processed_{0}, n_resets_{0}, n_time_jumps_{0},
      n_update_skips_{0}, n_filter_errors_{0}, n_stale_{0}, n_failed_{0}, n_imu_used_{0}, n_imu_dropped_{0},
      n_outputs_{0}, n_imu_outputs_{0}, n_relocalisations_{0}, n_relocalising_frames_{0};
  std::array<std::atomic<std::uint64_t>, ros_glue::kRejectCount> n_rejected_{};
  std::mutex stats_mu_;
  StageStats stages_;
  std::string last_filter_error_;
  std::string backend_name_ = "none (waiting for the first frame)";
  std::size_t backend_memory_ = 0;
  int n_landmarks_ = 0;
  std::uint64_t diag_prev_outputs_ = 0, diag_prev_accepted_ = 0, diag_prev_processed_ = 0, diag_prev_rejected_ = 0, diag_prev_dropped_ = 0;
  ros::WallTime diag_prev_time_;
};

}  // namespace hapi_eskf
