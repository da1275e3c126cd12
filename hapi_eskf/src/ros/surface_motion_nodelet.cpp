// hapi_eskf/SurfaceMotionNodelet (surface_motion_nodelet.hpp says what it
// reads and writes).
#include "surface_motion_nodelet.hpp"

#include "surface_motion_conversions.hpp"

#include <hapi_msgs/SurfaceMotion.h>
#include <pluginlib/class_list_macros.hpp>
#include <tf2_eigen/tf2_eigen.h>
#include <visualization_msgs/Marker.h>

namespace hapi_eskf {

using surface_motion::MotionStatus;

SurfaceMotionNodelet::~SurfaceMotionNodelet() {
  diag_timer_.stop();
  odom_sub_.shutdown();
  map_sub_.shutdown();
  flow_sub_.shutdown();
  info_sub_.shutdown();
  smoothed_srv_.shutdown();
}

void SurfaceMotionNodelet::onInit() {
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  hapi_nodelet_kit::ParamReader reader(pnh);
  ros_glue::readSurfaceMotionParams(reader, &params_);
  for (const std::string& w : reader.warnings()) NODELET_WARN("%s", w.c_str());
  if (!reader.ok()) return startup_.refuse(nh, pnh, getName(), "invalid parameters", reader.errors());

  estimator_ = std::make_unique<surface_motion::SurfaceMotionEstimator>(params_.estimator);
  odom_guard_ = std::make_unique<hapi_nodelet_kit::StampGuard>(params_.time_jump_reset);
  imaging_frame_ = params_.imaging_frame;
  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);

  motion_pub_ = pnh.advertise<hapi_msgs::SurfaceMotion>("surface_motion", 50);
  marker_pub_ = pnh.advertise<visualization_msgs::Marker>("surface_motion_marker", 5);
  smoothed_srv_ = pnh.advertiseService("smoothed_motion", &SurfaceMotionNodelet::smoothedService, this);
  updater_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
  updater_->setHardwareID(kHardwareId);
  updater_->add(kStatusName, [this](diagnostic_updater::DiagnosticStatusWrapper& stat) { stats_.diagnose(stat); });
  diag_timer_ = nh.createWallTimer(ros::WallDuration(params_.diagnostics_period),
                                   [this](const ros::WallTimerEvent&) { updater_->force_update(); });

  // Subscribe last: callbacks may run as soon as this returns.
  info_sub_ = nh.subscribe("imaging/camera_info", 2, &SurfaceMotionNodelet::cameraInfoCallback, this);
  map_sub_ = nh.subscribe("map", 2, &SurfaceMotionNodelet::mapCallback, this);
  flow_sub_ = nh.subscribe("flow", 20, &SurfaceMotionNodelet::flowCallback, this);
  odom_sub_ = nh.subscribe("odom", 400, &SurfaceMotionNodelet::odomCallback, this, ros::TransportHints().tcpNoDelay());
  NODELET_INFO("SurfaceMotionNodelet: pixel (%g, %g) (-1 = centre), imaging frame '%s', frame rate %g Hz",
               params_.estimator.pixel_u, params_.estimator.pixel_v,
               imaging_frame_.empty() ? "(from CameraInfo)" : imaging_frame_.c_str(), params_.frame_rate);
}

void SurfaceMotionNodelet::cameraInfoCallback(const sensor_msgs::CameraInfoConstPtr& msg) {
  surface_motion::ImagingCamera cam;
  const std::string why = ros_glue::toImagingCamera(*msg, params_.frame_rate, &cam);
  std::lock_guard<std::mutex> lk(mu_);
  if (imaging_frame_.empty()) imaging_frame_ = msg->header.frame_id;
  if (!why.empty() || msg->header.frame_id != imaging_frame_) {
    ++stats_.camera_info_rejected;
    NODELET_ERROR_THROTTLE(2.0, "imaging CameraInfo rejected: %s",
                           why.empty() ? ("frame '" + msg->header.frame_id + "' is not ~imaging_frame '" +
                                          imaging_frame_ + "'").c_str()
                                       : why.c_str());
    return;
  }
  estimator_->setCamera(cam);
}

void SurfaceMotionNodelet::mapCallback(const sensor_msgs::PointCloud2ConstPtr& msg) {
  ++stats_.maps_received;
  std::vector<Vec3> pts;
  const std::string why = ros_glue::toPoints(*msg, &pts);
  std::lock_guard<std::mutex> lk(mu_);
  const bool wrong_frame = !world_frame_.empty() && msg->header.frame_id != world_frame_;
  if (!why.empty() || wrong_frame) {
    ++stats_.maps_rejected;
    NODELET_ERROR_THROTTLE(2.0, "map rejected: %s",
                           why.empty() ? ("frame '" + msg->header.frame_id + "' is not the odometry's '" +
                                          world_frame_ + "'").c_str()
                                       : why.c_str());
    return;
  }
  map_frame_ = msg->header.frame_id;
  estimator_->setMap(std::move(pts));
}

void SurfaceMotionNodelet::flowCallback(const hapi_msgs::ImageFlowConstPtr& msg) {
  ++stats_.flows_received;
  std::lock_guard<std::mutex> lk(mu_);
  if (!imaging_frame_.empty() && msg->header.frame_id != imaging_frame_) {
    ++stats_.flows_wrong_frame;
    NODELET_ERROR_THROTTLE(2.0, "flow dropped: frame '%s' is not the imaging camera's '%s'",
                           msg->header.frame_id.c_str(), imaging_frame_.c_str());
    return;
  }
  std::string why;
  const surface_motion::FlowOutcome o = estimator_->addFlow(ros_glue::toFlowMeasurement(*msg), &why);
  stats_.countFlow(o);
  // A flow without a valid measurement (first frame, too few features) is
  // the front end's normal answer: counted, not an error.
  const bool bad = (o == surface_motion::FlowOutcome::kInvalid && msg->status == hapi_msgs::ImageFlow::STATUS_OK) ||
                   o == surface_motion::FlowOutcome::kOutOfOrder;
  if (bad) NODELET_ERROR_THROTTLE(2.0, "flow dropped (%s): %s", surface_motion::toString(o), why.c_str());
  if (const auto out = estimator_->outputWithNewFlows()) publish(*out, ros::Time(out->t));
}

std::string SurfaceMotionNodelet::extrinsic(const std::string& child, Eigen::Isometry3d* T) {
  if (imaging_frame_.empty()) return "no ~imaging_frame and no CameraInfo yet";
  if (T_child_imaging_ && extrinsic_child_ == child) {
    *T = *T_child_imaging_;
    return "";
  }
  if (child == imaging_frame_) {
    T_child_imaging_ = Eigen::Isometry3d::Identity();
  } else {
    std::string err;
    if (!tf_buffer_->canTransform(child, imaging_frame_, ros::Time(0), &err))
      return "no TF from '" + child + "' to the imaging frame '" + imaging_frame_ + "': " + err;
    T_child_imaging_ = tf2::transformToEigen(tf_buffer_->lookupTransform(child, imaging_frame_, ros::Time(0)));
  }
  extrinsic_child_ = child;
  *T = *T_child_imaging_;
  return "";
}

void SurfaceMotionNodelet::odomCallback(const nav_msgs::OdometryConstPtr& msg) {
  ++stats_.odom_received;
  std::lock_guard<std::mutex> lk(mu_);
  const hapi_nodelet_kit::StampCheck sc = odom_guard_->check(static_cast<std::int64_t>(msg->header.stamp.toNSec()));
  if (sc.verdict == hapi_nodelet_kit::StampVerdict::kReject) {
    ++stats_.odom_rejected;
    NODELET_ERROR_THROTTLE(2.0, "odometry dropped: stamp %.6f not after %.6f", msg->header.stamp.toSec(),
                           sc.previousSec());
    return;
  }
  if (sc.verdict == hapi_nodelet_kit::StampVerdict::kReset) {
    ++stats_.time_jumps;
    NODELET_WARN("odometry stamp went back %.3f s: surface motion restarted", sc.backSec());
    estimator_->reset();
  }
  if (world_frame_.empty()) world_frame_ = msg->header.frame_id;
  if (msg->header.frame_id != world_frame_ || msg->child_frame_id.empty()) {
    ++stats_.odom_rejected;
    NODELET_ERROR_THROTTLE(2.0, "odometry dropped: frame '%s' (expected '%s'), child frame '%s'",
                           msg->header.frame_id.c_str(), world_frame_.c_str(), msg->child_frame_id.c_str());
    return;
  }
  Eigen::Isometry3d T_child_imaging;
  const std::string no_extrinsic = extrinsic(msg->child_frame_id, &T_child_imaging);
  if (!no_extrinsic.empty()) {
    NODELET_ERROR_THROTTLE(5.0, "surface motion: %s", no_extrinsic.c_str());
    publish(estimator_->statusOutput(msg->header.stamp.toSec(), MotionStatus::kNoExtrinsic, no_extrinsic),
            msg->header.stamp);
    return;
  }
  const auto out =
      estimator_->addOdometry(surface_motion::toRigidlyAttached(ros_glue::toCameraOdometry(*msg), T_child_imaging));
  for (surface_motion::FlowOutcome o : estimator_->pendingOutcomes()) stats_.countFlow(o);
  if (!out) {
    ++stats_.odom_rejected;
    NODELET_ERROR_THROTTLE(2.0, "odometry dropped: not finite, beyond physical bounds or a quaternion not of unit length");
    return;
  }
  publish(*out, msg->header.stamp);
}

void SurfaceMotionNodelet::publish(const surface_motion::SurfaceMotionOutput& out, const ros::Time& stamp) {
  stats_.countOutput(out.status);
  const std::optional<double> flow_stamp = estimator_->lastFusedFlowStamp();
  if (out.flow_fused && flow_stamp) stats_.flow_latency.add(ros::Time::now().toSec() - *flow_stamp);
  const std::string frame = imaging_frame_;
  const auto msg = boost::make_shared<hapi_msgs::SurfaceMotion>(ros_glue::toMessage(out, stamp, frame));
  motion_pub_.publish(msg);
  if (marker_pub_.getNumSubscribers() > 0) marker_pub_.publish(ros_glue::toMarker(*msg, params_.marker_scale));
}

bool SurfaceMotionNodelet::smoothedService(hapi_msgs::GetSurfaceMotion::Request& req,
                                           hapi_msgs::GetSurfaceMotion::Response& res) {
  ++stats_.smoothed_requests;
  std::lock_guard<std::mutex> lk(mu_);
  if (req.end < req.start) {
    res.success = false;
    res.message = "end is before start";
    return true;
  }
  for (const auto& o : estimator_->smoothed(req.start.toSec(), req.end.toSec()))
    res.motion.push_back(ros_glue::toMessage(o, ros::Time(o.t), imaging_frame_));
  res.success = !res.motion.empty();
  res.message = res.success ? "" : "no stored output in the interval (history_length: " +
                                       std::to_string(params_.estimator.history_length) + " s)";
  return true;
}

}  // namespace hapi_eskf

PLUGINLIB_EXPORT_CLASS(hapi_eskf::SurfaceMotionNodelet, nodelet::Nodelet)
