// StereoFrontendNodelet (stereo_frontend_nodelet.hpp): start-up, stamp checks
// of the synchronised inputs, and the worker that runs the pipeline.
#include "stereo_frontend_nodelet.hpp"

#include "image_input.hpp"
#include "landmarks_message.hpp"

#include <hapi_msgs/StereoLandmarks.h>
#include <pluginlib/class_list_macros.hpp>

#include <boost/make_shared.hpp>

#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <sstream>

namespace hapi_frontend {
namespace {

// Fields of CameraInfo that define the calibration (header and stamp excluded).
bool sameCalibration(const sensor_msgs::CameraInfo& a, const sensor_msgs::CameraInfo& b) {
  return a.width == b.width && a.height == b.height && a.distortion_model == b.distortion_model && a.D == b.D &&
         a.K == b.K && a.R == b.R && a.P == b.P && a.binning_x == b.binning_x && a.binning_y == b.binning_y &&
         a.roi.x_offset == b.roi.x_offset && a.roi.y_offset == b.roi.y_offset && a.roi.width == b.roi.width &&
         a.roi.height == b.roi.height;
}

}  // namespace

StereoFrontendNodelet::~StereoFrontendNodelet() {
  // Stop the inputs first: unsubscribing waits for running callbacks, so
  // none can touch the mailbox while the members below are destroyed.
  diag_timer_.stop();
  input_.shutdown();
  mailbox_.close();  // wakes the worker, which then returns
  if (worker_.joinable()) worker_.join();
}

void StereoFrontendNodelet::onInit() {
  ros::NodeHandle& nh = getMTNodeHandle();
  ros::NodeHandle& pnh = getMTPrivateNodeHandle();

  hapi_nodelet_kit::ParamReader reader(pnh);
  readFrontendParams(reader, &params_);
  for (const auto& w : reader.warnings()) NODELET_WARN("%s", w.c_str());
  if (!reader.ok())
    return startup_.refuse(getNodeHandle(), getPrivateNodeHandle(), getName(), "invalid parameters",
                           reader.errors());
  try {
    pipeline_ = std::make_unique<StereoPipeline>(params_.pipeline);
  } catch (const std::exception& ex) {
    return startup_.refuse(getNodeHandle(), getPrivateNodeHandle(), getName(), "pipeline creation failed",
                           {ex.what()});
  }
  stamp_guard_ = std::make_unique<hapi_nodelet_kit::StampGuard>(params_.time_jump_reset);
  self_check_ = std::make_unique<FrontendSelfCheck>(params_.self_check);
  if (!subscribeImages(nh, pnh)) return;

  // Nothing can fail from here on. (The manager runs none of this nodelet's
  // callbacks before onInit returns, so the order below is free.)
  startDiagnostics();
  pub_ = pnh.advertise<hapi_msgs::StereoLandmarks>("landmarks", 10);
  worker_ = std::thread(&StereoFrontendNodelet::workerLoop, this);

  // No max-interval limit in the approximate policy: pairs beyond the slop
  // reach onSynced and are rejected there, so they are counted and logged.
  using namespace std::placeholders;
  input_.synchronise(nh, params_.queue_size, params_.approximate_sync,
                     std::bind(&StereoFrontendNodelet::onSynced, this, _1, _2, _3, _4),
                     std::bind(&StereoFrontendNodelet::onExactDrop, this, _1, _2, _3, _4));

  NODELET_INFO(
      "stereo front end: detector %s%s, N=%d, %s sync (queue %d), transport '%s'; inputs %s -> %s",
      params_.pipeline.detector.c_str(), params_.pipeline.use_gpu ? " (GPU requested)" : "",
      params_.pipeline.landmarks_per_frame, params_.approximate_sync ? "approximate" : "exact", params_.queue_size,
      params_.image_transport.c_str(), input_.topics().c_str(), pub_.getTopic().c_str());
}

bool StereoFrontendNodelet::subscribeImages(ros::NodeHandle& nh, ros::NodeHandle& pnh) {
  const std::string why = input_.subscribeImages(nh, pnh, params_.image_transport, params_.queue_size);
  if (why.empty()) return true;
  startup_.refuse(getNodeHandle(), getPrivateNodeHandle(), getName(),
                  "image transport '" + params_.image_transport + "' unavailable", {why});
  return false;
}

void StereoFrontendNodelet::startDiagnostics() {
  updater_ = std::make_unique<diagnostic_updater::Updater>(getNodeHandle(), getPrivateNodeHandle(), getName());
  updater_->setHardwareID(kHardwareId);
  updater_->add(kStatusName, &diag_, &FrontendDiagnostics::produce);
  updater_->add(kSelfCheckName, self_check_.get(), &FrontendSelfCheck::produce);
  // Wall timer + force_update: diagnostics keep flowing when simulated time
  // pauses or jumps backwards (bag loops).
  diag_timer_ = getNodeHandle().createWallTimer(ros::WallDuration(std::max(0.1, updater_->getPeriod())),
                                                [this](const ros::WallTimerEvent&) { updater_->force_update(); });
}

void StereoFrontendNodelet::reject(const std::string& reason, const std::string& detail) {
  diag_.rejected(reason, detail);
  if (error_log_.shouldLog(reason)) NODELET_ERROR("rejected stereo frame [%s]: %s", reason.c_str(), detail.c_str());
}

void StereoFrontendNodelet::onExactDrop(const sensor_msgs::ImageConstPtr&, const sensor_msgs::CameraInfoConstPtr&,
                                        const sensor_msgs::ImageConstPtr&, const sensor_msgs::CameraInfoConstPtr&) {
  // Exact sync found no partner with the same stamp (unsynchronised cameras,
  // lost message): the incomplete set is discarded.
  diag_.dropped("unpaired");
  NODELET_WARN_THROTTLE(5.0, "dropping messages without an exactly time-matched stereo partner "
                             "(cameras not hardware-synchronised? try ~approximate_sync: true)");
}

void StereoFrontendNodelet::onSynced(const sensor_msgs::ImageConstPtr& l, const sensor_msgs::CameraInfoConstPtr& li,
                                     const sensor_msgs::ImageConstPtr& r, const sensor_msgs::CameraInfoConstPtr& ri) {
  const ros::Time stamp = l->header.stamp;
  if (params_.approximate_sync) {
    const double d_lr = std::fabs((l->header.stamp - r->header.stamp).toSec());
    const double d_li = std::fabs((l->header.stamp - li->header.stamp).toSec());
    const double d_ri = std::fabs((r->header.stamp - ri->header.stamp).toSec());
    const double worst = std::max(d_lr, std::max(d_li, d_ri));
    if (worst > params_.approx_slop) {
      std::ostringstream os;
      os << "stamps differ by " << worst * 1e3 << " ms > approx_slop " << params_.approx_slop * 1e3 << " ms";
      reject("unsynchronised", os.str());
      return;
    }
  }
  const hapi_nodelet_kit::StampCheck sc = stamp_guard_->check(static_cast<std::int64_t>(stamp.toNSec()));
  if (sc.verdict == hapi_nodelet_kit::StampVerdict::kReject) {
    ros::Time previous;
    previous.fromNSec(static_cast<uint64_t>(sc.previous_ns));
    std::ostringstream os;
    os << "stamp " << stamp << " not after the previous " << previous;
    reject("stamp_not_increasing", os.str());
    return;
  }
  if (sc.verdict == hapi_nodelet_kit::StampVerdict::kReset) {
    // Bag loop or simulator restart: the front end has no temporal state,
    // so it restarts cleanly; the back end sees the jump in the stamps.
    diag_.timeReset();
    NODELET_WARN("image stamps jumped back by %.3f s: time reset, continuing", sc.backSec());
  }
  if (mailbox_.put(Frame{l, r, li, ri})) diag_.dropped("busy");  // the worker is behind: newest frame wins
}

void StereoFrontendNodelet::workerLoop() {
  while (std::optional<Frame> frame = mailbox_.take()) {  // empty once closed
    try {
      processFrame(*frame);
    } catch (const std::exception& ex) {
      // Last line of defence: a bug in the core must not take the manager
      // (and with it the back end) down.
      reject("internal_error", ex.what());
    }
  }
}

bool StereoFrontendNodelet::updateCalibration(const Info& left, const Info& right) {
  if (calib_ok_ && sameCalibration(left, calib_left_) && sameCalibration(right, calib_right_)) return true;
  calib_ok_ = false;
  CameraCalib cl, cr;
  if (const InputError e = toCalib(left, &cl)) {
    reject(e.reason, "left camera_info: " + e.detail);
    return false;
  }
  if (const InputError e = toCalib(right, &cr)) {
    reject(e.reason, "right camera_info: " + e.detail);
    return false;
  }
  const std::string why = pipeline_->setCalibration(cl, cr);
  if (!why.empty()) {
    reject("invalid_calibration", why);
    return false;
  }
  calib_left_ = left;
  calib_right_ = right;
  calib_ok_ = true;
  const StereoRig& rig = pipeline_->rig();
  NODELET_INFO("stereo calibration (%s, %ux%u): baseline %.4f m, t_lr = [%.4f %.4f %.4f]",
               left.distortion_model.c_str(), left.width, left.height, rig.t_lr.norm(), rig.t_lr.x(), rig.t_lr.y(),
               rig.t_lr.z());
  return true;
}

void StereoFrontendNodelet::processFrame(const Frame& f) {
  GreyImage left, right;
  if (const InputError e = toGrey(f.left, params_.mono16_bits, &left)) return reject(e.reason, "left: " + e.detail);
  if (const InputError e = toGrey(f.right, params_.mono16_bits, &right)) return reject(e.reason, "right: " + e.detail);
  if (const InputError e = checkPairSizes(left, right, *f.left_info, *f.right_info)) return reject(e.reason, e.detail);
  std_msgs::Header header = f.left->header;
  if (header.frame_id.empty()) header.frame_id = f.left_info->header.frame_id;
  if (header.frame_id.empty()) return reject("missing_frame_id", "left image and camera_info have no frame_id");
  if (!updateCalibration(*f.left_info, *f.right_info)) return;

  StereoFrameResult result;
  const std::string why = pipeline_->process(left.gray, right.gray, left.colour, &result);
  if (!why.empty()) return reject("core_rejected", why);
  if (params_.pipeline.use_gpu && !result.used_gpu && !warned_no_gpu_) {
    warned_no_gpu_ = true;
    NODELET_WARN("~use_gpu is true but the frame ran on the CPU path (no CUDA device or build without CUDA)");
  }

  auto msg = boost::make_shared<hapi_msgs::StereoLandmarks>();
  const std::string bad = fillLandmarksMsg(result, header, msg.get());
  if (!bad.empty()) return reject("internal_error", bad);
  diag_.frameProcessed(result);
  self_check_->frameProcessed(result);
  pub_.publish(msg);  // shared pointer: zero-copy to nodelets in the same manager
  diag_.landmarksPublished((ros::Time::now() - header.stamp).toSec());
}

}  // namespace hapi_frontend

PLUGINLIB_EXPORT_CLASS(hapi_frontend::StereoFrontendNodelet, nodelet::Nodelet)
