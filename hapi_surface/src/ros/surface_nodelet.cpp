// hapi_surface/SurfaceNodelet (surface_nodelet.hpp says what it reads and
// writes).
#include "surface_nodelet.hpp"

#include "surface_conversions.hpp"

#include "hapi_surface/depth_image_contract.hpp"
#include "hapi_surface/mesh_extraction.hpp"
#include "hapi_surface/ply_io.hpp"
#include "hapi_surface/textured_obj.hpp"
#ifdef HAPI_SURFACE_WITH_CUDA
#include "hapi_surface/cuda/surface_volume_cuda.hpp"
#endif

#include <pluginlib/class_list_macros.hpp>
#include <tf2_eigen/tf2_eigen.h>
#include <visualization_msgs/Marker.h>

#include <cmath>

namespace hapi_surface {

using ros_glue::SurfaceStatistics;

SurfaceNodelet::~SurfaceNodelet() {
  diag_timer_.stop();
  mesh_timer_.stop();
  depth_info_sub_.shutdown();
  imaging_info_sub_.shutdown();
  confidence_sub_.shutdown();
  path_sub_.shutdown();
  odom_sub_.shutdown();
  depth_sub_.unsubscribe();
  imaging_sub_.unsubscribe();
  save_srv_.shutdown();
}

void SurfaceNodelet::onInit() {
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  hapi_nodelet_kit::ParamReader reader(pnh);
  ros_glue::readSurfaceParams(reader, &params_);
  for (const std::string& w : reader.warnings()) NODELET_WARN("%s", w.c_str());
  if (!reader.ok()) return startup_.refuse(nh, pnh, getName(), "invalid parameters", reader.errors());

#ifdef HAPI_SURFACE_WITH_CUDA
  std::string gpu;
  if (params_.use_cuda && surfaceCudaAvailable(&gpu)) {
    cuda_ = std::make_unique<CudaSurfaceVolume>();
    stats_.on_gpu = true;
    NODELET_INFO("SurfaceNodelet: TSDF integration on %s", gpu.c_str());
  }
#endif
  resetMapper();
  depth_guard_ = std::make_unique<hapi_nodelet_kit::StampGuard>(params_.time_jump_reset);
  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);
  mesh_pub_ = pnh.advertise<visualization_msgs::Marker>("mesh", 1, true);
  save_srv_ = pnh.advertiseService("save_surface", &SurfaceNodelet::saveService, this);
  updater_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
  updater_->setHardwareID(kHardwareId);
  updater_->add(kStatusName, [this](diagnostic_updater::DiagnosticStatusWrapper& stat) { stats_.diagnose(stat); });
  diag_timer_ = nh.createWallTimer(ros::WallDuration(params_.diagnostics_period),
                                   [this](const ros::WallTimerEvent&) { updater_->force_update(); });
  mesh_timer_ = nh.createWallTimer(ros::WallDuration(params_.mesh_period),
                                   [this](const ros::WallTimerEvent&) { publishMesh(); });

  // Subscribe last: callbacks may run as soon as this returns.
  auto camera_info = [this](std::optional<PinholeCamera>* camera) {
    return boost::function<void(const sensor_msgs::CameraInfoConstPtr&)>(
        [this, camera](const sensor_msgs::CameraInfoConstPtr& msg) {
          PinholeCamera c;
          const SurfaceStatus st = ros_glue::toCamera(*msg, &c);
          if (st != SurfaceStatus::kOk) {
            stats_.reject(&stats_.camera_info_rejected, st);
            NODELET_ERROR_THROTTLE(2.0,
                                   "CameraInfo of '%s' rejected: %s (needs a positive K, distortion model plumb_bob "
                                   "or none; depth images rectified)",
                                   msg->header.frame_id.c_str(), toString(st));
            return;
          }
          std::lock_guard<std::mutex> lk(mu_);
          *camera = c;
        });
  };
  depth_info_sub_ = nh.subscribe<sensor_msgs::CameraInfo>(kDepthInfoTopic, 2, camera_info(&depth_camera_));
  imaging_info_sub_ = nh.subscribe<sensor_msgs::CameraInfo>("imaging/camera_info", 2, camera_info(&imaging_camera_));
  if (params_.use_confidence)
    confidence_sub_ = nh.subscribe(kConfidenceTopic, params_.queue_size, &SurfaceNodelet::confidenceCallback, this);
  path_sub_ = nh.subscribe("path", 1, &SurfaceNodelet::pathCallback, this);
  odom_sub_ = nh.subscribe("odom", 50, &SurfaceNodelet::odomCallback, this);
  subscribeWithTf(kDepthTopic, &depth_sub_, &depth_filter_, &SurfaceNodelet::depthCallback, &stats_.depth_no_tf);
  subscribeWithTf("imaging/image", &imaging_sub_, &imaging_filter_, &SurfaceNodelet::imagingCallback,
                  &stats_.imaging_no_tf);
  const VoxelGrid g = VoxelGrid::centredAt(Eigen::Vector3d::Zero(), params_.core);
  NODELET_INFO("SurfaceNodelet: %d x %d x %d voxels of %.2f mm in '%s'%s", g.dims.x(), g.dims.y(), g.dims.z(),
               params_.core.voxel_size * 1e3, params_.world_frame.c_str(),
               params_.use_confidence ? ", depth weighted by its confidence" : "");
}

void SurfaceNodelet::resetMapper() {
  mapper_ = std::make_unique<SurfaceMapper>(params_.core);
#ifdef HAPI_SURFACE_WITH_CUDA
  if (cuda_) {
    // The CPU takes over what the GPU could not do (same result).
    mapper_->setIntegrator([this](TsdfVolume* v, const DepthFrame& f) {
      const SurfaceStatus st = cuda_->integrateHost(v, f);
      return st == SurfaceStatus::kDeviceError ? v->integrate(f) : st;
    });
    mapper_->setMesher([this](const TsdfVolume& v) {
      Mesh m;
      const bool ok = cuda_->upload(v) == SurfaceStatus::kOk && cuda_->extractMesh(&m) == SurfaceStatus::kOk;
      return ok ? m : extractMesh(v);
    });
  }
#endif
  last_path_.clear();
  last_projection_ = ros::Time();
  std::lock_guard<std::mutex> lk(odom_mu_);
  odom_.clear();
}

void SurfaceNodelet::subscribeWithTf(const std::string& topic, message_filters::Subscriber<sensor_msgs::Image>* sub,
                                     std::unique_ptr<ImageFilter>* filter,
                                     void (SurfaceNodelet::*cb)(const sensor_msgs::ImageConstPtr&),
                                     SurfaceStatistics::Counter* no_tf) {
  ros::NodeHandle& nh = getNodeHandle();
  sub->subscribe(nh, topic, params_.queue_size);
  *filter = std::make_unique<ImageFilter>(*sub, *tf_buffer_, params_.world_frame, params_.queue_size, nh);
  (*filter)->registerCallback(boost::bind(cb, this, boost::placeholders::_1));
  (*filter)->registerFailureCallback(
      [this, topic, no_tf](const sensor_msgs::ImageConstPtr& msg, tf2_ros::filter_failure_reasons::FilterFailureReason) {
        ++*no_tf;
        NODELET_ERROR_THROTTLE(5.0, "%s dropped: no TF '%s' -> '%s' at %.6f", topic.c_str(),
                               params_.world_frame.c_str(), msg->header.frame_id.c_str(), msg->header.stamp.toSec());
      });
}

std::optional<Eigen::Isometry3d> SurfaceNodelet::poseAt(const std::string& frame, const ros::Time& stamp) const {
  try {
    return tf2::transformToEigen(tf_buffer_->lookupTransform(params_.world_frame, frame, stamp));
  } catch (const tf2::TransformException&) {
    return std::nullopt;
  }
}

void SurfaceNodelet::confidenceCallback(const sensor_msgs::ImageConstPtr& msg) {
  std::lock_guard<std::mutex> lk(mu_);
  confidence_.push_back(msg);
  while (confidence_.size() > static_cast<std::size_t>(2 * params_.queue_size)) confidence_.pop_front();
}

FloatImage SurfaceNodelet::confidenceAt(const ros::Time& stamp) {
  FloatImage out;
  for (const auto& c : confidence_)
    if (c->header.stamp == stamp && toConfidenceImage(ros_glue::rawView(*c), &out) == SurfaceStatus::kOk) return out;
  ++stats_.confidence_missing;
  return FloatImage();
}

void SurfaceNodelet::depthCallback(const sensor_msgs::ImageConstPtr& msg) {
  ++stats_.depth_received;
  DepthFrame frame;
  SurfaceStatus st = msg->encoding == kDepthEncoding ? toFloatImage(ros_glue::rawView(*msg), &frame.depth)
                                                     : SurfaceStatus::kUnknownEncoding;
  const std::optional<Eigen::Isometry3d> pose = poseAt(msg->header.frame_id, msg->header.stamp);
  std::lock_guard<std::mutex> lk(mu_);
  const hapi_nodelet_kit::StampCheck sc = depth_guard_->check(static_cast<std::int64_t>(msg->header.stamp.toNSec()));
  if (sc.verdict == hapi_nodelet_kit::StampVerdict::kReject) {
    ++stats_.depth_out_of_order;
    NODELET_ERROR_THROTTLE(2.0, "depth image dropped: stamp %.6f not after %.6f", msg->header.stamp.toSec(),
                           sc.previousSec());
    return;
  }
  if (sc.verdict == hapi_nodelet_kit::StampVerdict::kReset) {
    ++stats_.time_jumps;
    NODELET_WARN("depth stamp went back %.3f s: the surface starts again", sc.backSec());
    resetMapper();
  }
  if (st == SurfaceStatus::kOk && !depth_camera_) st = SurfaceStatus::kBadCamera;
  FrameUse use = FrameUse::kRejected;
  takeOdometry();
  if (st == SurfaceStatus::kOk) {
    frame.camera = *depth_camera_;
    if (params_.use_confidence) frame.weight = confidenceAt(msg->header.stamp);
    st = mapper_->addDepthFrame(msg->header.stamp.toSec(), std::move(frame), pose, &use);
  }
  if (st != SurfaceStatus::kOk) {
    stats_.reject(&stats_.depth_rejected, st);
    NODELET_ERROR_THROTTLE(2.0, "depth image dropped (%s): encoding '%s' (needs %s), %ux%u%s", toString(st),
                           msg->encoding.c_str(), kDepthEncoding, msg->width, msg->height,
                           depth_camera_ ? "" : ", no depth_camera_info yet");
    return;
  }
  ++(use == FrameUse::kKeyframe ? stats_.keyframes : use == FrameUse::kWaiting ? stats_.keyframes_unsettled
                                                                               : stats_.depth_skipped);
  countKeyframes();
}

void SurfaceNodelet::countKeyframes() {
  stats_.keyframes_stored = mapper_->keyframes().size();
  const WaitingCounts w = mapper_->waitingCounts();
  stats_.keyframes_waiting = w.waiting;
  stats_.early_keyframes_fused = w.fused;
  stats_.early_keyframes_discarded = w.discarded;
  stats_.keyframes_registered = w.registered;
  stats_.keyframes_unregistered = w.unregistered;
}

void SurfaceNodelet::odomCallback(const nav_msgs::OdometryConstPtr& msg) {
  const auto& C = msg->pose.covariance;  // row-major 6 x 6: x y z, then rotation about x y z
  PoseUncertainty u;
  u.stamp = msg->header.stamp.toSec();
  u.position_std = std::sqrt(C[0] + C[7] + C[14]);
  u.rotation_std = std::sqrt(C[21] + C[28] + C[35]);
  if (!std::isfinite(u.position_std) || !std::isfinite(u.rotation_std)) {
    ++stats_.odom_rejected;
    NODELET_ERROR_THROTTLE(5.0, "odometry at %.6f ignored: its pose covariance has a negative or non-finite variance",
                           u.stamp);
    return;
  }
  // Not under mu_: odometry comes at the IMU rate and must not wait for an
  // integration (it would hold the manager's threads); the depth callback
  // hands the buffered uncertainties to the mapper.
  std::lock_guard<std::mutex> lk(odom_mu_);
  odom_.push_back(u);
}

void SurfaceNodelet::takeOdometry() {
  std::vector<PoseUncertainty> batch;
  {
    std::lock_guard<std::mutex> lk(odom_mu_);
    batch.swap(odom_);
  }
  for (const PoseUncertainty& u : batch) mapper_->addPoseUncertainty(u);
}

void SurfaceNodelet::imagingCallback(const sensor_msgs::ImageConstPtr& msg) {
  ++stats_.imaging_received;
  {
    std::lock_guard<std::mutex> lk(mu_);
    if (!last_projection_.isZero() && msg->header.stamp >= last_projection_ &&
        (msg->header.stamp - last_projection_).toSec() < params_.imaging_period) {
      ++stats_.imaging_throttled;
      return;
    }
  }
  FloatImage image;
  SurfaceStatus st = toFloatImage(ros_glue::rawView(*msg), &image);
  const std::optional<Eigen::Isometry3d> pose = poseAt(msg->header.frame_id, msg->header.stamp);
  std::lock_guard<std::mutex> lk(mu_);
  if (st == SurfaceStatus::kOk && !imaging_camera_) st = SurfaceStatus::kBadCamera;
  if (st == SurfaceStatus::kOk) st = mapper_->addImagingFrame(image, *imaging_camera_, pose).status;
  // Before the first keyframe there is no surface yet: not an error.
  if (st == SurfaceStatus::kNoVolume) return;
  if (st != SurfaceStatus::kOk) {
    stats_.reject(&stats_.imaging_rejected, st);
    NODELET_ERROR_THROTTLE(2.0, "imaging frame dropped (%s): encoding '%s' (one of %s), %ux%u%s", toString(st),
                           msg->encoding.c_str(), floatEncodingsText(), msg->width, msg->height,
                           imaging_camera_ ? "" : ", no imaging/camera_info yet");
    return;
  }
  last_projection_ = msg->header.stamp;
  ++stats_.imaging_projected;
}

void SurfaceNodelet::pathCallback(const nav_msgs::PathConstPtr& msg) {
  if (msg->header.frame_id != params_.world_frame) {
    NODELET_ERROR_THROTTLE(10.0, "path ignored: frame '%s' is not ~world_frame '%s'", msg->header.frame_id.c_str(),
                           params_.world_frame.c_str());
    return;
  }
  std::map<std::uint64_t, Eigen::Isometry3d> path;
  for (const auto& p : msg->poses) {
    Eigen::Isometry3d T;
    tf2::fromMsg(p.pose, T);
    path[p.header.stamp.toNSec()] = T;
  }
  std::lock_guard<std::mutex> lk(mu_);
  // A keyframe moves with the correction of the filter pose of its stamp
  // (the depth camera is rigidly attached to the path's frame).
  auto corrected = [&](double stamp, const Eigen::Isometry3d& current) -> std::optional<Eigen::Isometry3d> {
    const std::uint64_t ns = ros::Time(stamp).toNSec();
    const auto a = last_path_.find(ns), b = path.find(ns);
    if (a == last_path_.end() || b == path.end()) return std::nullopt;
    return b->second * a->second.inverse() * current;
  };
  if (!last_path_.empty() && mapper_->correctPoses(corrected)) {
    ++stats_.rebuilds;
    NODELET_INFO("surface rebuilt from %zu keyframes after a pose correction", mapper_->keyframes().size());
  }
  countKeyframes();
  last_path_ = std::move(path);
}

std::vector<Rgb8> SurfaceNodelet::colours(const Mesh& mesh) const {
  float lo = static_cast<float>(params_.colour_min), hi = static_cast<float>(params_.colour_max);
  if (params_.auto_colour_range) valueRange(mesh.values, &lo, &hi);
  std::vector<Rgb8> c(mesh.vertices.size());
  for (std::size_t i = 0; i < c.size(); ++i) c[i] = jetColour(mesh.values[i], lo, hi);
  return c;
}

void SurfaceNodelet::publishMesh() {
  // Meshing is the surface's largest CPU cost (docs/DESIGN.md "Surface", Cost):
  // without a subscriber it is left to the imaging projection and ~save_surface.
  if (mesh_pub_.getNumSubscribers() == 0) return;
  Mesh mesh;
  {
    std::lock_guard<std::mutex> lk(mu_);
    if (!mapper_->volume()) return;
    mesh = mapper_->mesh();
  }
  stats_.vertices = mesh.vertices.size();
  stats_.faces = mesh.faces.size();
  mesh_pub_.publish(ros_glue::toMarker(mesh, colours(mesh), params_.world_frame, ros::Time::now()));
  ++stats_.meshes_published;
}

bool SurfaceNodelet::saveService(hapi_msgs::SaveSurface::Request& req, hapi_msgs::SaveSurface::Response& res) {
  Mesh mesh;
  {
    std::lock_guard<std::mutex> lk(mu_);
    if (mapper_->volume()) mesh = mapper_->mesh();
  }
  stats_.vertices = mesh.vertices.size();
  stats_.faces = mesh.faces.size();
  // A path ending in .obj: OBJ + MTL + PNG texture of the values (textured_obj.hpp); else PLY.
  const SurfaceStatus st = mesh.empty()             ? SurfaceStatus::kNoVolume
                           : isObjPath(req.path) ? writeTexturedObj(req.path, mesh, colours(mesh))
                                                 : writePly(req.path, mesh, colours(mesh));
  res.success = st == SurfaceStatus::kOk;
  res.vertices = static_cast<std::uint32_t>(mesh.vertices.size());
  res.faces = static_cast<std::uint32_t>(mesh.faces.size());
  res.message = res.success ? "wrote " + req.path : std::string(toString(st)) + ": " + req.path;
  ++(res.success ? stats_.saves : stats_.saves_failed);
  if (!res.success) NODELET_ERROR("save_surface: %s", res.message.c_str());
  return true;
}

}  // namespace hapi_surface

PLUGINLIB_EXPORT_CLASS(hapi_surface::SurfaceNodelet, nodelet::Nodelet)
