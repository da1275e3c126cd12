// hapi_eskf/EskfNodelet: thin ROS wrapper of a hapi_eskf::SlamBackend (the
// ES-EKF or another algorithm, ~backend_algorithm: slam_backend.hpp). It wires the
// node (parameters, topics, services, timers) and runs the worker that owns
// the filter; the outputs and bookkeeping are separate objects, each with its
// own lock:
//   OutputPublisher    ~odom, ~pose, TF, the IMU-rate output (output_publisher.hpp)
//   TrajectoryRecorder ~path, ~save_trajectory (trajectory_recorder.hpp)
//   MapPublisher       map snapshots, ~map, ~save_map (map_publisher.hpp)
//   MapSession         ~map_file, ~load_map, the stereo calibration (map_session.hpp)
//   GraphRefiner       ~refine: batch refinement of the run (graph_refiner.hpp)
//   ImuInput           ~use_imu: sample checks, mounting rotation, buffer (imu_input.hpp)
//   NodeletStatistics  counters, stage timings, /diagnostics (statistics.hpp)
//   SelfCheck          the self-checks of clock, IMU, start and landmarks (self_check.hpp)
//
// Start-up: ~ parameters are read and checked once (params.hpp); an invalid
// one, a ~backend_algorithm not built into the library, or ~backend=cuda
// without a usable device or without the device memory for the pool while
// ~allow_cpu_fallback is false, is a start-up failure: the nodelet stays loaded but inert, with
// FATAL lines and an ERROR "filter" status on /diagnostics
// (hapi_nodelet_kit/startup_failure.hpp, the policy of every HAPI nodelet).
//
// Threads: ROS callbacks only validate and convert (O(N), no filter access);
// they post the frame into a newest-wins hapi_nodelet_kit::Mailbox. One
// worker thread owns the filter (all back-end calls, so GPU work never blocks a
// callback), publishes odom/pose/path/TF per frame and refreshes the map
// snapshot that a wall timer publishes at ~map_publish_rate. With ~use_imu
// the IMU callback publishes odom/pose/TF once per gyro sample from a
// propagated copy of the pose (pose_propagator.hpp, a pose-block step, never the
// filter): outputs at the IMU rate that keep flowing while the worker is busy
// with a frame.
//
// GPU faults: a backend error during a frame drops the frame and discards
// the filter; BackendFaultPolicy decides between a restart on a new backend,
// the CPU backend (~allow_cpu_fallback) and a clean stop (ERROR status).
//
// Resets (service ~reset, or a stamp jumping backwards by more than
// ~time_jump_reset: hapi_nodelet_kit::StampGuard) bump an epoch; frames carry
// the epoch they were accepted in, and the worker resets the filter when it
// sees a newer epoch, so a frame of the old timeline can never reach the
// fresh filter.
#pragma once

#include "hapi_eskf/backend/slam_backend.hpp"
#include "hapi_eskf/covariance/backend_fault_policy.hpp"
#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "hapi_eskf/keyframes/keyframe_recorder.hpp"
#include "hapi_eskf/ros/graph_refiner.hpp"
#include "hapi_eskf/ros/imu_input.hpp"
#include "hapi_eskf/ros/map_publisher.hpp"
#include "hapi_eskf/ros/map_session.hpp"
#include "hapi_eskf/ros/output_publisher.hpp"
#include "hapi_eskf/ros/params.hpp"
#include "hapi_eskf/ros/self_check.hpp"
#include "hapi_eskf/ros/statistics.hpp"
#include "hapi_eskf/ros/trajectory_recorder.hpp"
#include "hapi_eskf/ros/validation.hpp"

#include <diagnostic_updater/diagnostic_updater.h>
#include <hapi_msgs/LoadMap.h>
#include <hapi_msgs/StereoLandmarks.h>
#include <hapi_nodelet_kit/mailbox.hpp>
#include <hapi_nodelet_kit/stamp_guard.hpp>
#include <hapi_nodelet_kit/startup_failure.hpp>
#include <hapi_nodelet_kit/watched_subscriber.hpp>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

namespace hapi_eskf {

class EskfNodelet : public nodelet::Nodelet {
 public:
  EskfNodelet() = default;
  ~EskfNodelet() override;

 private:
  // The /diagnostics status of the filter ("<node>: filter"), also the one
  // that reports a start-up failure.
  static constexpr const char* kStatusName = "filter";
  static constexpr const char* kHardwareId = "hapi_eskf";
  static constexpr const char* kSelfCheckName = "self-check";

  struct Work {
    StereoFrame frame;
    std::string frame_id;
    ros::Time stamp;  // the message's own stamp: outputs carry it exactly (no double round trip)
    std::uint64_t epoch = 0;
  };

  void onInit() override;
  // The start-up checks; false when the nodelet must not run (reported).
  bool checkStartup();
  void landmarksCallback(const hapi_msgs::StereoLandmarks::ConstPtr& msg);
  void imuCallback(const sensor_msgs::Imu::ConstPtr& msg);
  bool resetService(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  bool loadMapService(hapi_msgs::LoadMap::Request& req, hapi_msgs::LoadMap::Response& res);
  // Asks the worker for a filter reset; true once it acknowledged (within 2 s).
  bool requestReset();
  void reject(ros_glue::Reject r, const std::string& detail);

  // --- worker thread only ---
  void workerLoop();
  void resetFilter();
  bool ensureFilter(const Work& w);
  bool anchorWorld(const Work& w);
  void applyImu(double up_to);
  bool process(Work& w);  // false: frame not used (error counted)
  // A backend fault (Status::kBackendError) in the frame at `stamp`: reported,
  // the frame dropped, then BackendFaultPolicy's action (restart, CPU, stop).
  bool onBackendFault(double stamp);
  // The filter stops for good: frames are counted as failed, the
  // diagnostics status turns ERROR with `why`.
  void stop(const std::string& why);
  void takeSnapshot();
  ros_glue::FileMap fileMap();  // the pool and the keyframes as a map file's content (~save_map)
  void recordKeyframe(const StereoFrame& frame);

  ros_glue::NodeletParams params_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;

  std::unique_ptr<ros_glue::NodeletStatistics> stats_;
  std::unique_ptr<ros_glue::SelfCheck> self_check_;
  std::unique_ptr<ros_glue::ImuInput> imu_;  // ~use_imu only
  std::unique_ptr<ros_glue::OutputPublisher> output_;
  std::unique_ptr<ros_glue::TrajectoryRecorder> trajectory_;
  std::unique_ptr<ros_glue::MapPublisher> map_;
  std::unique_ptr<ros_glue::MapSession> map_session_;
  std::unique_ptr<KeyframeRecorder> keyframes_;  // for ~save_map
  std::unique_ptr<ros_glue::GraphRefiner> refiner_;  // ~refine

  // Landmarks callback state (and ~reset's stamp guard clear): the guard owns
  // its lock, input_mu_ makes its verdict and the epoch read one step.
  std::mutex input_mu_;
  ros_glue::ValidationConfig validation_;
  std::unique_ptr<hapi_nodelet_kit::StampGuard> stamp_guard_;
  std::string camera_frame_;  // locked by ~camera_frame or the first accepted message

  hapi_nodelet_kit::Mailbox<Work> mailbox_;
  std::atomic<std::uint64_t> epoch_{0};         // bumped by every reset request
  std::atomic<std::uint64_t> worker_epoch_{0};  // the epoch the filter runs in
  std::thread worker_;
  std::atomic<bool> stop_{false};

  // Worker-owned filter state.
  std::unique_ptr<SlamBackend> backend_;
  BackendFaultPolicy fault_policy_{true};  // set from ~allow_cpu_fallback at start-up
  bool stopped_ = false;
  bool need_init_ = true;
  bool extrinsic_applied_ = false;  // the camera-IMU extrinsic from TF is in the filter
  ros::Time last_stamp_;

  // Entry points, declared last so that they go first: the destructor stops
  // them (and joins the worker) before any member they use is destroyed.
  // startup_ reports a start-up failure (then nothing else is started).
  hapi_nodelet_kit::StartupFailure startup_{kStatusName, kHardwareId};
  hapi_nodelet_kit::WatchedSubscriber landmarks_in_, imu_in_;
  ros::Subscriber left_info_in_, right_info_in_;
  ros::ServiceServer reset_srv_, save_map_srv_, load_map_srv_, save_traj_srv_, refine_srv_;
  ros::WallTimer map_timer_, diag_timer_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
};

}  // namespace hapi_eskf
