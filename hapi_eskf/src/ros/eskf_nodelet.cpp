#include "hapi_eskf/ros/eskf_nodelet.hpp"

#include "hapi_eskf/ros/conversions.hpp"

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Path.h>
#include <pluginlib/class_list_macros.hpp>
#include <sensor_msgs/PointCloud2.h>

#include <sys/stat.h>

#include <iterator>
#include <stdexcept>

namespace hapi_eskf {

using ros_glue::Reject;

namespace {

Eigen::Isometry3d toIsometry(const geometry_msgs::Transform& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z).normalized()
                   .toRotationMatrix();
  T.translation() = Vec3(t.translation.x, t.translation.y, t.translation.z);
  return T;
}

geometry_msgs::Transform toTransform(const Eigen::Isometry3d& T) {
  geometry_msgs::Transform t;
  const Eigen::Quaterniond q(T.linear());
  t.translation.x = T.translation().x();
  t.translation.y = T.translation().y();
  t.translation.z = T.translation().z();
  t.rotation.w = q.w();
  t.rotation.x = q.x();
  t.rotation.y = q.y();
  t.rotation.z = q.z();
  return t;
}

constexpr double kMiB = 1024.0 * 1024.0;

}  // namespace

EskfNodelet::~EskfNodelet() {
  // Stop every entry point first: timers and callbacks use members (updater_,
  // publishers) that are destroyed before them in declaration order.
  map_timer_.stop();
  diag_timer_.stop();
  landmarks_sub_.shutdown();
  imu_sub_.shutdown();
  reset_srv_.shutdown();
  save_map_srv_.shutdown();
  save_traj_srv_.shutdown();
  stop_ = true;
  mailbox_.close();
  snapshot_cv_.notify_all();
  if (worker_.joinable()) worker_.join();
}

void EskfNodelet::onInit() {
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();

  const std::string err = ros_glue::loadParams(pnh, &params_);
  if (!err.empty()) {
    NODELET_FATAL("invalid parameters: %s", err.c_str());
    throw std::runtime_error("hapi_eskf/EskfNodelet: invalid parameters: " + err);
  }
  if (!params_.unknown.empty()) {
    std::string names;
    for (const std::string& n : params_.unknown) names += (names.empty() ? "~" : ", ~") + n;
    NODELET_WARN("unknown parameter(s) ignored: %s (misspelled? every parameter is listed in config/eskf.yaml)",
                 names.c_str());
  }
  // Fail at start-up, not at the first frame, when the requested backend
  // cannot run (the descriptor length is only known from the first message).
  if (params_.filter.backend == BackendKind::kCuda) {
    std::string why;
    if (!cudaBackendAvailable(&why)) {
      if (!params_.allow_cpu_fallback) {
        NODELET_FATAL("~backend=cuda but CUDA is unavailable (%s) and ~allow_cpu_fallback is false", why.c_str());
        throw std::runtime_error("hapi_eskf/EskfNodelet: CUDA backend unavailable: " + why);
      }
      NODELET_WARN("*** ~backend=cuda but CUDA is unavailable (%s): FALLING BACK TO THE CPU BACKEND "
                   "(set ~allow_cpu_fallback:=false to make this fatal) ***",
                   why.c_str());
      params_.filter.backend = BackendKind::kCpu;
    }
  }
  {
    struct stat st {};
    if (stat(params_.output_dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
      NODELET_WARN("~output_dir '%s' is not an existing directory: ~save_map/~save_trajectory will fail",
                   params_.output_dir.c_str());
  }

  validation_.max_measurements = static_cast<std::uint32_t>(params_.max_measurements_per_msg);
  validation_.expected_frame = params_.camera_frame;
  camera_frame_ = params_.camera_frame;
  stamp_guard_ = std::make_unique<ros_glue::StampGuard>(params_.time_jump_reset);

  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  // Listen only when a lookup is needed (IMU mounting, base frame): otherwise
  // the node would buffer its own high-rate TF for nothing.
  if (params_.use_imu || !params_.base_frame.empty())
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);
  tf_broadcaster_ = std::make_unique<tf2_ros::TransformBroadcaster>();
  if (params_.use_imu) propagator_ = std::make_unique<ros_glue::PosePropagator>(params_.filter);

  // Topics are relative to the nodelet's namespace/name: a nodelet named
  // `eskf` publishes /eskf/odom etc. (private handle) and reads `landmarks`
  // from there too, remapped by the launch file to the front end's output.
  odom_pub_ = pnh.advertise<nav_msgs::Odometry>("odom", 10);
  pose_pub_ = pnh.advertise<geometry_msgs::PoseWithCovarianceStamped>("pose", 10);
  path_pub_ = pnh.advertise<nav_msgs::Path>("path", 1, true);
  map_pub_ = pnh.advertise<sensor_msgs::PointCloud2>("map", 1, true);

  reset_srv_ = pnh.advertiseService("reset", &EskfNodelet::resetService, this);
  save_map_srv_ = pnh.advertiseService("save_map", &EskfNodelet::saveMapService, this);
  save_traj_srv_ = pnh.advertiseService("save_trajectory", &EskfNodelet::saveTrajectoryService, this);

  updater_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
  updater_->setHardwareID("hapi_eskf");
  updater_->add("filter", this, &EskfNodelet::diagnose);
  diag_prev_time_ = ros::WallTime::now();
  diag_timer_ = nh.createWallTimer(ros::WallDuration(params_.diagnostics_period),
                                   [this](const ros::WallTimerEvent&) { updater_->force_update(); });
  map_timer_ = nh.createWallTimer(ros::WallDuration(1.0 / params_.map_publish_rate), &EskfNodelet::mapTimer, this);

  worker_ = std::thread(&EskfNodelet::workerLoop, this);

  // Subscribe last: callbacks may run as soon as this returns.
  // The ROS queue only has to absorb a burst until the (fast) callback runs;
  // rate mismatch is handled by the mailbox, where drops are counted.
  landmarks_sub_ = pnh.subscribe("landmarks", 10, &EskfNodelet::landmarksCallback, this,
                                 ros::TransportHints().tcpNoDelay());
  if (params_.use_imu) imu_sub_ = nh.subscribe(params_.imu_topic, 200, &EskfNodelet::imuCallback, this);

  NODELET_INFO("EskfNodelet: backend %s/%s, K_max %d, world_frame '%s', camera_frame '%s', base_frame '%s', imu %s",
               toString(params_.filter.backend), toString(params_.filter.precision), params_.filter.max_landmarks,
               params_.world_frame.c_str(), camera_frame_.empty() ? "(from first message)" : camera_frame_.c_str(),
               params_.base_frame.c_str(), params_.use_imu ? params_.imu_topic.c_str() : "off");
}

// ---------------------------------------------------------------- callbacks

void EskfNodelet::reject(Reject r, const std::string& detail) {
  ++n_rejected_[static_cast<int>(r)];
  NODELET_ERROR_THROTTLE(1.0, "rejected StereoLandmarks (%s): %s", ros_glue::rejectName(r), detail.c_str());
}

void EskfNodelet::landmarksCallback(const hapi_msgs::StereoLandmarks::ConstPtr& msg) {
  ++n_received_;
  Work w;
  {
    std::lock_guard<std::mutex> lk(input_mu_);
    const ros_glue::ValidationResult v = ros_glue::validateLandmarks(*msg, validation_);
    if (!v.ok()) {
      reject(v.reason, v.detail);
      return;
    }
    const ros_glue::StampCheck sc = stamp_guard_->check(msg->header.stamp.toSec());
    if (sc == ros_glue::StampCheck::kReject) {
      reject(Reject::kStampBackwards, "stamp " + std::to_string(msg->header.stamp.toSec()) +
                                          " not newer than the last accepted " +
                                          std::to_string(stamp_guard_->last()));
      return;
    }
    if (sc == ros_glue::StampCheck::kReset) {
      ++n_time_jumps_;
      NODELET_WARN("time jumped backwards (bag loop / clock reset) to %.3f: resetting the filter and the path",
                   msg->header.stamp.toSec());
      ++epoch_;
    }
    // The first accepted message fixes the camera frame and, once it carries
    // landmarks, the descriptor type and length of the pool.
    if (camera_frame_.empty()) {
      camera_frame_ = msg->header.frame_id;
      validation_.expected_frame = camera_frame_;
    }
    if (validation_.descriptor_length == 0 && !msg->landmarks.empty()) {
      validation_.descriptor_length = msg->descriptor_length;
      validation_.descriptor_type = msg->descriptor_type;
    }
    w.frame_id = camera_frame_;
    w.stamp = msg->header.stamp;
    w.epoch = epoch_.load();
  }
  ++n_accepted_;
  w.frame = ros_glue::toStereoFrame(*msg);
  mailbox_.put(std::move(w));  // an untaken older frame is dropped and counted by the mailbox
}

void EskfNodelet::imuCallback(const sensor_msgs::Imu::ConstPtr& msg) {
  const Vec3 g(msg->angular_velocity.x, msg->angular_velocity.y, msg->angular_velocity.z);
  const double stamp = msg->header.stamp.toSec();
  if (!g.allFinite() || !std::isfinite(stamp)) {
    ++n_imu_dropped_;
    NODELET_ERROR_THROTTLE(1.0, "dropping IMU sample with non-finite angular velocity or stamp");
    return;
  }
  Eigen::Quaterniond q_ci;
  {
    std::lock_guard<std::mutex> lk(input_mu_);
    if (camera_frame_.empty()) {  // the camera frame is not known before the first landmarks message
      ++n_imu_dropped_;
      return;
    }
    if (last_imu_stamp_ >= 0.0 && last_imu_stamp_ - stamp > params_.time_jump_reset) {
      std::lock_guard<std::mutex> lk2(imu_mu_);
      imu_buffer_.clear();  // samples of the old timeline would never be consumed
    } else if (last_imu_stamp_ >= 0.0 && stamp <= last_imu_stamp_) {
      // The buffer is kept in stamp order (the propagation relies on it).
      ++n_imu_dropped_;
      NODELET_WARN_THROTTLE(2.0, "IMU sample at %.6f not newer than the previous one (%.6f): dropped", stamp,
                            last_imu_stamp_);
      return;
    }
    last_imu_stamp_ = stamp;
    const std::string& f = msg->header.frame_id;
    auto it = imu_to_camera_.find(f);
    if (it == imu_to_camera_.end()) {
      if (f.empty() || f == camera_frame_) {
        it = imu_to_camera_.emplace(f, Eigen::Quaterniond::Identity()).first;
      } else {
        // Static mounting assumed: the rotation is looked up once, non-blocking.
        try {
          const auto t = tf_buffer_->lookupTransform(camera_frame_, f, ros::Time(0));
          it = imu_to_camera_.emplace(f, Eigen::Quaterniond(toIsometry(t.transform).linear())).first;
        } catch (const tf2::TransformException& e) {
          ++n_imu_dropped_;
          NODELET_WARN_THROTTLE(2.0, "no TF %s <- %s yet, IMU sample dropped: %s", camera_frame_.c_str(), f.c_str(),
                                e.what());
          return;
        }
      }
    }
    q_ci = it->second;
  }
  const ImuSample sample{stamp, msg->header.stamp, q_ci * g};
  {
    std::lock_guard<std::mutex> lk(imu_mu_);
    imu_buffer_.push_back(sample);
    while (static_cast<int>(imu_buffer_.size()) > params_.imu_buffer_size) {
      imu_buffer_.pop_front();
      ++n_imu_dropped_;
    }
  }
  // IMU-rate output right here (a 12x12 step, no filter access), so it keeps
  // flowing while the worker is busy with a frame.
  std::lock_guard<std::mutex> lk(out_mu_);
  stepAndPublish(sample);
}

bool EskfNodelet::resetService(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  const std::uint64_t target = ++epoch_;
  {
    std::lock_guard<std::mutex> lk(input_mu_);
    stamp_guard_->clear();  // the next frame starts the new filter, whatever its stamp
  }
  // The worker resets within one loop period (it wakes at least every 50 ms).
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(2.0);
  while (worker_epoch_.load() < target && ros::WallTime::now() < deadline) ros::WallDuration(0.005).sleep();
  res.success = worker_epoch_.load() >= target;
  res.message = res.success ? "filter reset; the next frame initialises it" : "worker did not acknowledge the reset";
  return true;
}

bool EskfNodelet::waitForSnapshot(std::uint64_t after,
                                  std::shared_ptr<const std::vector<ros_glue::MapPoint>>* out) {
  snapshot_requested_ = true;
  std::unique_lock<std::mutex> lk(snapshot_mu_);
  snapshot_cv_.wait_for(lk, std::chrono::seconds(2), [&] { return snapshot_generation_ > after || stop_; });
  *out = snapshot_;
  return snapshot_generation_ > after;
}

bool EskfNodelet::saveMapService(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  std::uint64_t gen;
  {
    std::lock_guard<std::mutex> lk(snapshot_mu_);
    gen = snapshot_generation_;
  }
  std::shared_ptr<const std::vector<ros_glue::MapPoint>> snap;
  if (!waitForSnapshot(gen, &snap)) {
    res.success = false;
    res.message = "no fresh map snapshot from the worker within 2 s";
    return true;
  }
  const std::string path = ros_glue::timestampedPath(params_.output_dir, "hapi_map", "ply");
  const std::string err = ros_glue::writePly(path, snap ? *snap : std::vector<ros_glue::MapPoint>{});
  res.success = err.empty();
  res.message = res.success ? path : err;
  if (res.success)
    NODELET_INFO("saved %zu map points to %s", snap ? snap->size() : 0, path.c_str());
  else
    NODELET_ERROR("~save_map failed: %s", err.c_str());
  return true;
}

bool EskfNodelet::saveTrajectoryService(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  std::vector<ros_glue::StampedPose> poses;
  {
    std::lock_guard<std::mutex> lk(path_mu_);
    poses.assign(trajectory_.begin(), trajectory_.end());
  }
  const std::string path = ros_glue::timestampedPath(params_.output_dir, "hapi_trajectory", "tum");
  const std::string err = ros_glue::writeTum(path, poses);
  res.success = err.empty();
  res.message = res.success ? path : err;
  if (res.success)
    NODELET_INFO("saved %zu poses (TUM) to %s", poses.size(), path.c_str());
  else
    NODELET_ERROR("~save_trajectory failed: %s", err.c_str());
  return true;
}

void EskfNodelet::mapTimer(const ros::WallTimerEvent&) {
  std::shared_ptr<const std::vector<ros_glue::MapPoint>> snap;
  ros::Time stamp;
  {
    std::lock_guard<std::mutex> lk(snapshot_mu_);
    if (snapshot_generation_ == published_generation_ || !snapshot_) return;
    published_generation_ = snapshot_generation_;
    snap = snapshot_;
    stamp = snapshot_stamp_;
  }
  sensor_msgs::PointCloud2 cloud = ros_glue::toPointCloud2(*snap);
  cloud.header.stamp = stamp;
  cloud.header.frame_id = params_.world_frame;
  map_pub_.publish(cloud);
}

// ------------------------------------------------------------------- worker

void EskfNodelet::workerLoop() {
  while (!stop_) {
    std::optional<Work> w = mailbox_.take(std::chrono::milliseconds(50));
    if (stop_) break;
    const std::uint64_t epoch = epoch_.load();
    if (epoch > worker_epoch_.load()) {
      resetFilter();
      worker_epoch_ = epoch;
    }
    if (w) {
      if (w->epoch < worker_epoch_.load()) {
        ++n_stale_;  // accepted before a reset: belongs to the old timeline
      } else {
        try {
          if (!process(*w)) ++n_failed_;
        } catch (const std::exception& e) {  // never let the worker die (e.g. std::bad_alloc)
          ++n_filter_errors_;
          ++n_failed_;
          NODELET_ERROR_THROTTLE(1.0, "exception while processing a frame: %s", e.what());
        }
      }
    }
    if (snapshot_requested_.exchange(false) ||
        (ros::WallTime::now() - last_snapshot_wall_).toSec() >= 1.0 / params_.map_publish_rate)
      takeSnapshot();
  }
}

void EskfNodelet::resetFilter() {
  ++n_resets_;
  need_init_ = true;
  {
    std::lock_guard<std::mutex> lk(imu_mu_);
    imu_buffer_.clear();
  }
  {
    std::lock_guard<std::mutex> lk(path_mu_);
    trajectory_.clear();
  }
  {
    std::lock_guard<std::mutex> lk(out_mu_);
    last_output_stamp_ = -1.0;  // the new timeline may start earlier
    if (propagator_) propagator_->invalidate();
  }
  tf_buffer_->clear();  // after a bag loop its data lies in the "future" of the new timeline
  nav_msgs::Path empty;
  empty.header.frame_id = params_.world_frame;
  empty.header.stamp = last_stamp_;
  path_pub_.publish(empty);
  if (eskf_) eskf_->reset(PoseState(), 0.0);  // empties the pool now: the map snapshot below is empty
  takeSnapshot();
  NODELET_WARN("filter reset (#%llu): path and map cleared", static_cast<unsigned long long>(n_resets_.load()));
}

bool EskfNodelet::ensureFilter(const Work& w) {
  if (eskf_) return true;
  if (w.frame.measurements.empty()) return false;  // the descriptor length is not known yet
  std::string err;
  std::unique_ptr<CovarianceBackend> backend = makeBackend(params_.filter, w.frame.descriptor_length, &err);
  if (!backend && params_.filter.backend == BackendKind::kCuda && params_.allow_cpu_fallback) {
    NODELET_WARN("*** CUDA backend could not be created (%s): FALLING BACK TO THE CPU BACKEND ***", err.c_str());
    params_.filter.backend = BackendKind::kCpu;
    backend = makeBackend(params_.filter, w.frame.descriptor_length, &err);
  }
  if (!backend) {
    ++n_filter_errors_;
    NODELET_ERROR_THROTTLE(5.0, "cannot create the %s backend: %s", toString(params_.filter.backend), err.c_str());
    return false;
  }
  eskf_ = std::make_unique<Eskf>(params_.filter, std::move(backend));
  {
    std::lock_guard<std::mutex> lk(stats_mu_);
    backend_name_ = eskf_->backend().name();
    backend_memory_ = eskf_->backend().memoryBytes();
  }
  NODELET_INFO("filter created: backend %s, %.1f MiB, descriptor length %d", eskf_->backend().name(),
               eskf_->backend().memoryBytes() / kMiB, w.frame.descriptor_length);
  return true;
}

// REP-105: with ~base_frame the published map is anchored at the FIRST BASE
// pose (T_map_world = T_base_cam, the filter's world being the first camera),
// so map is level with the robot instead of having the optical frame's
// z-forward axes. The camera mounting is looked up once (assumed rigid).
bool EskfNodelet::anchorWorld(const Work& w) {
  if (params_.base_frame.empty()) {
    std::lock_guard<std::mutex> lk(out_mu_);
    T_map_world_.setIdentity();
    T_cam_base_.setIdentity();
    return true;
  }
  try {
    const auto t = tf_buffer_->lookupTransform(params_.base_frame, w.frame_id, ros::Time(0), ros::Duration(0.2));
    const Eigen::Isometry3d T_base_cam = toIsometry(t.transform);
    std::lock_guard<std::mutex> lk(out_mu_);
    T_map_world_ = T_base_cam;
    T_cam_base_ = T_base_cam.inverse();
    return true;
  } catch (const tf2::TransformException& e) {
    ++n_filter_errors_;
    NODELET_ERROR_THROTTLE(2.0, "~base_frame set but no TF %s <- %s: %s (frame skipped)", params_.base_frame.c_str(),
                           w.frame_id.c_str(), e.what());
    return false;
  }
}

void EskfNodelet::applyImu(double up_to) {
  std::vector<ImuSample> samples;
  {
    std::lock_guard<std::mutex> lk(imu_mu_);
    while (!imu_buffer_.empty() && imu_buffer_.front().stamp <= up_to) {
      samples.push_back(imu_buffer_.front());
      imu_buffer_.pop_front();
    }
  }
  for (const ImuSample& s : samples) {
    if (s.stamp <= eskf_->time()) continue;  // older than the filter: nothing to predict
    const Status st = eskf_->predictWithGyro(s.stamp, s.gyro_camera, params_.gyro_noise_density);
    if (st == Status::kOk) {
      ++n_imu_used_;
    } else {
      ++n_imu_dropped_;
      NODELET_WARN_THROTTLE(2.0, "predictWithGyro failed: %s", toString(st));
    }
  }
}

bool EskfNodelet::process(Work& w) {
  if (!ensureFilter(w)) return false;
  const double stamp = w.frame.stamp;
  Status st = Status::kOk;
  IterationReport rep;
  if (need_init_) {
    if (!anchorWorld(w)) return false;
    st = eskf_->reset(PoseState(), stamp);
    if (st != Status::kOk) {
      ++n_filter_errors_;
      NODELET_ERROR_THROTTLE(1.0, "filter reset failed: %s", toString(st));
      return false;
    }
    need_init_ = false;
    std::lock_guard<std::mutex> lk(imu_mu_);  // samples before the first frame are not needed
    while (!imu_buffer_.empty() && imu_buffer_.front().stamp <= stamp) imu_buffer_.pop_front();
  } else if (params_.use_imu) {
    applyImu(stamp);
  }
  const ros::WallTime t0 = ros::WallTime::now();
  if (w.frame.measurements.empty()) {
    st = eskf_->predictTo(stamp);  // nothing seen: keep the motion model running
    rep.t_total_ms = rep.t_predict_ms = (ros::WallTime::now() - t0).toSec() * 1e3;
    rep.n_landmarks = eskf_->numLandmarks();
  } else {
    st = eskf_->processFrame(w.frame, &rep);
  }
  if (st != Status::kOk) {
    ++n_filter_errors_;
    {
      std::lock_guard<std::mutex> lk(stats_mu_);
      last_filter_error_ = toString(st);
    }
    NODELET_ERROR_THROTTLE(1.0, "filter rejected the frame at %.3f: %s (state unchanged)", stamp, toString(st));
    return false;
  }
  ++n_processed_;
  if (rep.relocalised) {
    ++n_relocalisations_;
    NODELET_WARN("relocalised against the map at %.3f after an input gap (EskfSettings relocalise_gap)", stamp);
  }
  if (rep.relocalising) {
    // Lost after an input gap: the pose is a stale prediction, so nothing is
    // published until a frame the map supports has relocalised the filter.
    ++n_relocalising_frames_;
    NODELET_WARN_THROTTLE(1.0, "lost after an input gap: waiting for a frame the map supports (no output)");
    return true;
  }
  if (rep.update_skipped) {
    ++n_update_skips_;
    NODELET_WARN_THROTTLE(1.0, "update skipped at %.3f (innovation covariance not PD): prediction only", stamp);
  }
  {
    std::lock_guard<std::mutex> lk(stats_mu_);
    StageStats& s = stages_;
    ++s.n;
    s.sum.t_predict_ms += rep.t_predict_ms;
    s.sum.t_association_ms += rep.t_association_ms;
    s.sum.t_update_ms += rep.t_update_ms;
    s.sum.t_removal_ms += rep.t_removal_ms;
    s.sum.t_addition_ms += rep.t_addition_ms;
    s.sum.t_total_ms += rep.t_total_ms;
    s.sum.n_measurements += rep.n_measurements;
    s.sum.n_updated += rep.n_updated;
    s.sum.n_added += rep.n_added;
    s.sum.n_removed += rep.n_removed;
    s.sum.n_gated_out += rep.n_gated_out;
    s.sum.mean_nis += rep.mean_nis;
    s.last = rep;
    n_landmarks_ = eskf_->numLandmarks();
    backend_memory_ = eskf_->backend().memoryBytes();
  }
  last_stamp_ = w.stamp;
  const Mat12 C = eskf_->poseCovariance();
  nav_msgs::Odometry odom;
  {
    std::lock_guard<std::mutex> lk(out_mu_);
    output_frame_ = w.frame_id;
    odom = makeOdometry(last_stamp_, eskf_->pose(), C);
    // With ~use_imu the IMU-rate output may already be past this frame
    // (front-end latency): outputs keep strictly increasing stamps, and the
    // corrected state reaches the next ones through the re-based propagation.
    if (stamp > last_output_stamp_) publishOutput(odom);
    if (propagator_) {
      propagator_->rebase(eskf_->pose(), C, stamp);
      // Catch up with the samples already received after this frame (their
      // outputs are out already unless one arrived during this block).
      std::vector<ImuSample> later;
      {
        std::lock_guard<std::mutex> lk2(imu_mu_);
        for (const ImuSample& s : imu_buffer_)
          if (s.stamp > stamp) later.push_back(s);
      }
      for (const ImuSample& s : later) stepAndPublish(s);
    }
  }
  recordPath(odom);
  return true;
}

void EskfNodelet::stepAndPublish(const ImuSample& s) {
  if (!propagator_ || !propagator_->valid() || s.stamp <= propagator_->time()) return;
  const Status st = propagator_->step(s.stamp, s.gyro_camera, params_.gyro_noise_density);
  if (st != Status::kOk) {
    NODELET_WARN_THROTTLE(2.0, "IMU-rate propagation failed at %.3f: %s", s.stamp, toString(st));
    return;
  }
  // One output per sample: the output rate is the IMU rate.
  if (s.stamp > last_output_stamp_) {
    publishOutput(makeOdometry(s.ros_stamp, propagator_->pose(), propagator_->covariance()));
    ++n_imu_outputs_;
  }
}

nav_msgs::Odometry EskfNodelet::makeOdometry(const ros::Time& stamp, const PoseState& pose, const Mat12& C) const {
  nav_msgs::Odometry odom;
  odom.header.stamp = stamp;
  odom.header.frame_id = params_.world_frame;
  odom.child_frame_id = output_frame_;
  odom.pose = ros_glue::toPoseWithCovariance(pose, C, T_map_world_);
  odom.twist = ros_glue::toTwistWithCovariance(pose, C);
  return odom;
}

void EskfNodelet::publishOutput(const nav_msgs::Odometry& odom) {
  last_output_stamp_ = odom.header.stamp.toSec();
  ++n_outputs_;
  odom_pub_.publish(odom);

  geometry_msgs::PoseWithCovarianceStamped ps;
  ps.header = odom.header;
  ps.pose = odom.pose;
  pose_pub_.publish(ps);

  if (params_.publish_tf) {
    // One parent per frame in TF: the camera (or base) frame's parent becomes
    // world_frame. With ~base_frame, T_map_base = T_map_cam * T_cam_base.
    const auto& op = odom.pose.pose;
    Eigen::Isometry3d T_map_cam = Eigen::Isometry3d::Identity();
    T_map_cam.linear() =
        Eigen::Quaterniond(op.orientation.w, op.orientation.x, op.orientation.y, op.orientation.z)
            .normalized()
            .toRotationMatrix();
    T_map_cam.translation() = Vec3(op.position.x, op.position.y, op.position.z);
    geometry_msgs::TransformStamped t;
    t.header = odom.header;
    if (params_.base_frame.empty()) {
      t.child_frame_id = odom.child_frame_id;
      t.transform = toTransform(T_map_cam);
    } else {
      t.child_frame_id = params_.base_frame;
      t.transform = toTransform(T_map_cam * T_cam_base_);
    }
    tf_broadcaster_->sendTransform(t);
  }
}

void EskfNodelet::recordPath(const nav_msgs::Odometry& odom) {
  const auto& op = odom.pose.pose;
  ros_glue::StampedPose sp;
  sp.stamp = odom.header.stamp.toSec();
  sp.p = Vec3(op.position.x, op.position.y, op.position.z);
  sp.q = Eigen::Quaterniond(op.orientation.w, op.orientation.x, op.orientation.y, op.orientation.z);
  nav_msgs::Path path;
  const bool want_path = path_pub_.getNumSubscribers() > 0;
  {
    std::lock_guard<std::mutex> lk(path_mu_);
    trajectory_.push_back(sp);
    while (static_cast<int>(trajectory_.size()) > params_.path_max_length) trajectory_.pop_front();
    if (want_path) {
      path.poses.reserve(trajectory_.size());
      for (const ros_glue::StampedPose& s : trajectory_) {
        geometry_msgs::PoseStamped p;
        p.header.stamp = ros::Time(s.stamp);
        p.header.frame_id = params_.world_frame;
        p.pose.position.x = s.p.x();
        p.pose.position.y = s.p.y();
        p.pose.position.z = s.p.z();
        p.pose.orientation.w = s.q.w();
        p.pose.orientation.x = s.q.x();
        p.pose.orientation.y = s.q.y();
        p.pose.orientation.z = s.q.z();
        path.poses.push_back(p);
      }
    }
  }
  if (want_path) {
    path.header = odom.header;
    path_pub_.publish(path);
  }
}

void EskfNodelet::takeSnapshot() {
  last_snapshot_wall_ = ros::WallTime::now();
  auto pts = std::make_shared<std::vector<ros_glue::MapPoint>>();
  if (eskf_ && !need_init_) *pts = ros_glue::toMapPoints(eskf_->landmarks(), T_map_world_);
  {
    std::lock_guard<std::mutex> lk(snapshot_mu_);
    snapshot_ = pts;
    snapshot_stamp_ = last_stamp_;
    ++snapshot_generation_;
  }
  snapshot_cv_.notify_all();
}

// -------------------------------------------------------------- diagnostics

void EskfNodelet::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  const ros::WallTime now = ros::WallTime::now();
  const double dt = std::max(1e-6, (now - diag_prev_time_).toSec());
  diag_prev_time_ = now;
  const std::uint64_t accepted = n_accepted_, processed = n_processed_, dropped = mailbox_.dropped(),
                      outputs = n_outputs_;
  std::uint64_t rejected = 0;
  for (const auto& r : n_rejected_) rejected += r.load();
  const double in_rate = (accepted - diag_prev_accepted_) / dt, proc_rate = (processed - diag_prev_processed_) / dt;
  const std::uint64_t new_rejected = rejected - diag_prev_rejected_, new_dropped = dropped - diag_prev_dropped_;
  const double out_rate = (outputs - diag_prev_outputs_) / dt;
  diag_prev_outputs_ = outputs;
  diag_prev_accepted_ = accepted;
  diag_prev_processed_ = processed;
  diag_prev_rejected_ = rejected;
  diag_prev_dropped_ = dropped;

  StageStats s;
  std::string backend, last_error;
  std::size_t memory;
  int landmarks;
  {
    std::lock_guard<std::mutex> lk(stats_mu_);
    s = stages_;
    stages_ = StageStats();
    stages_.last = s.last;
    backend = backend_name_;
    memory = backend_memory_;
    landmarks = n_landmarks_;
    last_error = last_filter_error_;
  }
  if (new_rejected > 0)
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::WARN, "%llu input messages rejected in the last %.1f s",
                  static_cast<unsigned long long>(new_rejected), dt);
  else if (new_dropped > 0)
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::WARN, "%llu frames dropped (processing slower than input)",
                  static_cast<unsigned long long>(new_dropped));
  else if (accepted == 0)
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "waiting for landmarks");
  else
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "running");

  const double n = std::max(1, s.n);
  stat.add("input_rate_hz", in_rate);
  stat.add("processing_rate_hz", proc_rate);
  // odom/pose/TF outputs per second: the frame rate, or the IMU rate with ~use_imu.
  stat.add("output_rate_hz", out_rate);
  stat.add("frames_received", n_received_.load());
  stat.add("frames_accepted", accepted);
  stat.add("frames_processed", processed);
  stat.add("frames_dropped", dropped);
  stat.add("frames_stale_after_reset", n_stale_.load());
  // Once idle: accepted == processed + dropped + stale_after_reset + failed.
  stat.add("frames_failed", n_failed_.load());
  stat.add("rejected_total", rejected);
  for (int r = 1; r < ros_glue::kRejectCount; ++r)
    stat.add(std::string("rejected_") + ros_glue::rejectName(static_cast<Reject>(r)), n_rejected_[r].load());
  stat.add("update_skips", n_update_skips_.load());
  stat.add("relocalisations", n_relocalisations_.load());
  stat.add("frames_relocalising", n_relocalising_frames_.load());
  stat.add("filter_errors", n_filter_errors_.load());
  stat.add("last_filter_error", last_error);
  stat.add("resets", n_resets_.load());
  stat.add("time_jumps", n_time_jumps_.load());
  stat.add("landmarks", landmarks);
  stat.add("backend", backend);
  stat.add("backend_memory_mib", memory / kMiB);
  // Mean per-stage wall time over the frames of this period [ms].
  stat.add("frames_in_period", s.n);
  stat.add("t_predict_ms", s.sum.t_predict_ms / n);
  stat.add("t_association_ms", s.sum.t_association_ms / n);
  stat.add("t_update_ms", s.sum.t_update_ms / n);
  stat.add("t_removal_ms", s.sum.t_removal_ms / n);
  stat.add("t_addition_ms", s.sum.t_addition_ms / n);
  stat.add("t_total_ms", s.sum.t_total_ms / n);
  stat.add("measurements_per_frame", s.sum.n_measurements / n);
  stat.add("updated_per_frame", s.sum.n_updated / n);
  stat.add("gated_out_per_frame", s.sum.n_gated_out / n);
  stat.add("added_per_frame", s.sum.n_added / n);
  stat.add("removed_per_frame", s.sum.n_removed / n);
  stat.add("mean_nis", s.sum.mean_nis / n);
  if (params_.use_imu) {
    stat.add("imu_samples_used", n_imu_used_.load());
    stat.add("imu_samples_dropped", n_imu_dropped_.load());
    stat.add("imu_rate_outputs", n_imu_outputs_.load());
  }
}

}  // namespace hapi_eskf

PLUGINLIB_EXPORT_CLASS(hapi_eskf::EskfNodelet, nodelet::Nodelet)
