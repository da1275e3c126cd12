// make_sim_bag: writes one scenario of the hand-held simulation suite
// (docs/DESIGN.md "Data") to a rosbag and/or a EuRoC/ASL folder.
//
//   make_sim_bag --scene globe|skin|patch|chessboard
//                --trajectory smooth|handheld|fast|loop|subject|rest|orbit|measurement|measurement_subject|stage|tremor|calibration
//                [--seed N] [--duration S] [--rate HZ] [--imu-rate HZ]
//                [--output FILE.bag] [--asl DIR]
//                [--exposure-ms MS] [--blur-samples N] [--photometric 0|1]
//                [--image-noise 0|1] [--imu-noise 0|1] [--image-scale S] [--texture PATH]
//                [--realism ideal|real] [--imaging-rate HZ] [--imaging-pixel U,V] [--stage-speed MM_S]
//                [--imaging-content texture|perfusion]
//                [--right-shift-px PX] [--camera-clock-offset S]
//
// Topics (frames as make_globe_bag's; every stamp from the fixed epoch 1e9 s):
//   /stereo/{left,right}/image_raw, camera_info  camera clock (t_imu - time offset)
//   /imu/data              sensor_msgs/Imu in imu_link, IMU rate, covariances of the noise model
//   /tf_static             left -> right optical, left optical -> imu_link (the extrinsic the
//                          device believes: the true one except under --realism real)
//   /calibration           (--realism real only) latched YAML as /ground_truth/calibration's, with
//                          the believed extrinsic and time offset: what a filter is told
//   /tf                    world -> ground_truth/stereo_left_optical_frame at each frame's true time
//   /ground_truth/pose     the same as PoseStamped
//   /ground_truth/odometry nav_msgs/Odometry at IMU rate: the left camera in world (the scene
//                          frame), twist in the child frame (REP-105)
//   /ground_truth/imu_odometry  the IMU in the inertial frame "inertial", IMU rate (equals world
//                          except where the scene moves: subject, measurement_subject, stage)
//   /ground_truth/scene    latched YAML of the scene's surfaces in world
//   /ground_truth/calibration  latched YAML: the true T_cam_imu, time_offset_s and its sign, IMU noise
//   /globe/info            (globe scene) latched, 1 Hz, as make_globe_bag
// With --imaging-rate HZ > 0 (none by default: the bag is then as without it):
//   /imaging/image_raw, camera_info  the imaging camera (the left camera at its own rate), mono8,
//                          frame imaging_optical_frame, camera clock; with --imaging-content
//                          perfusion 32FC1: the skin's perfusion pattern in PU (perfusion_pattern.hpp)
//   /ground_truth/perfusion  (--imaging-content perfusion) latched YAML of that pattern
//   /tf_static             also stereo_left_optical_frame -> imaging_optical_frame (identity)
//   /ground_truth/surface_motion  hapi_msgs/SurfaceMotion at IMU rate (true clock): the truth at
//                          the imaging pixel, status RAY_MISSES_MAP when its ray misses the scene
// Ground truth is stamped in the true (IMU) clock. Same arguments -> the same
// bytes (rosbag writes no wall-clock time).
#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <std_msgs/String.h>
#include <tf2_msgs/TFMessage.h>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>

#include "bag_messages.hpp"
#include "hapi_sim/asl_writer.hpp"
#include "hapi_sim/scenario.hpp"
#include "hapi_sim/scenario_options.hpp"

namespace {

using namespace hapi_sim;

using namespace hapi_dataset::recording_frames;
constexpr const char* kInertial = "inertial";
constexpr const char* kGtImu = "ground_truth/imu_link";
constexpr const char* kCaller = "/make_sim_bag";
constexpr const char* kImaging = "imaging_optical_frame";

struct Options {
  ScenarioConfig cfg;
  std::string output, asl;
  bool have_scene = false, have_trajectory = false;
};

[[noreturn]] void usage(const std::string& err) {
  std::cerr << "make_sim_bag: " << err << "\n"
            << "usage: make_sim_bag " << kScenarioOptionsUsage << "\n"
            << "  [--output FILE.bag] [--asl DIR]\n";
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  hapi_dataset::forEachOption(argc, argv, usage, [&](const std::string& k, const std::string& v) {
    if (setScenarioOption(k, v, &o.cfg)) {
      o.have_scene |= k == "--scene";
      o.have_trajectory |= k == "--trajectory";
    } else if (k == "--output") {
      o.output = v;
    } else if (k == "--asl") {
      o.asl = v;
    } else {
      usage("unknown option " + k);
    }
  });
  if (!o.have_scene || !o.have_trajectory) usage("--scene and --trajectory are required");
  if (o.output.empty() && o.asl.empty()) usage("give --output FILE.bag and/or --asl DIR");
  const std::string err = o.cfg.validate();
  if (!err.empty()) usage(err);
  return o;
}

std_msgs::String text(const std::string& s) {
  std_msgs::String m;
  m.data = s;
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  const Options opt = parse(argc, argv);
  const Scenario sc(opt.cfg);
  const bool globe = opt.cfg.scene == SceneKind::Globe;
  const bool imaging = sc.imagingCount() > 0;
  std::cerr << "[make_sim_bag] scene " << sc.scene().name() << ", trajectory " << trajectoryName(opt.cfg.trajectory)
            << ", seed " << opt.cfg.seed << ": " << sc.frameCount() << " stereo frames at " << opt.cfg.rate << " Hz, "
            << sc.imuCount() << " IMU samples at " << opt.cfg.imu_rate << " Hz";
  if (imaging)
    std::cerr << ", " << sc.imagingCount() << " imaging frames at " << opt.cfg.imaging_rate << " Hz (pixel "
              << sc.imagingPixel().x() << ", " << sc.imagingPixel().y() << ")";
  std::cerr << "\n";

  std::unique_ptr<rosbag::Bag> bag;
  if (!opt.output.empty()) {
    bag = std::make_unique<rosbag::Bag>();
    try {
      bag->open(opt.output, rosbag::bagmode::Write);
    } catch (const rosbag::BagException& e) {
      std::cerr << "make_sim_bag: cannot open '" << opt.output << "' for writing: " << e.what() << "\n";
      return 1;
    }
  }
  std::unique_ptr<AslWriter> asl;
  try {
    if (!opt.asl.empty()) asl = std::make_unique<AslWriter>(opt.asl, sc);
  } catch (const std::exception& e) {
    std::cerr << "make_sim_bag: " << e.what() << "\n";
    return 1;
  }

  const ros::Time t0 = stampAt(0);
  const CameraImuCalibration& told = sc.believedCalibration();
  const std_msgs::String globe_info =
      text(globeInfoYaml(sc.scene().surfaces()[0].radius, sc.scene().surfaces()[0].centre, kWorld, opt.cfg.seed,
                         sc.scene().textureSource()));
  if (bag) {
    tf2_msgs::TFMessage st;
    st.transforms.push_back(toTransformMsg(t0, kLeft, kRight, Eigen::Vector3d(sc.rig().baseline, 0, 0),
                                           Eigen::Quaterniond::Identity()));
    st.transforms.push_back(toTransformMsg(t0, kLeft, kImu, told.T_cam_imu.p, told.T_cam_imu.q));
    if (imaging)
      st.transforms.push_back(toTransformMsg(t0, kLeft, kImaging, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity()));
    bag->write("/tf_static", t0, st, latchedHeader<tf2_msgs::TFMessage>(kCaller));
    bag->write("/ground_truth/scene", t0, text(sc.scene().yaml()), latchedHeader<std_msgs::String>(kCaller));
    bag->write("/ground_truth/calibration", t0, text(sc.calibrationYaml()), latchedHeader<std_msgs::String>(kCaller));
    if (imaging && opt.cfg.imaging_content == ImagingContent::Perfusion)
      bag->write("/ground_truth/perfusion", t0, text(sc.perfusionPattern().yaml()),
                 latchedHeader<std_msgs::String>(kCaller));
    if (opt.cfg.realism != Realism::Ideal)
      bag->write("/calibration", t0, text(sc.believedCalibrationYaml()), latchedHeader<std_msgs::String>(kCaller));
  }
  const CameraInfoData ci_l = sc.rig().leftInfo(), ci_r = sc.rig().rightInfo(), ci_imaging = sc.imagingInfo();
  ImuModel imu_model = sc.makeImuModel();
  const double sg2 = std::pow(imu_model.gyroSigma(), 2), sa2 = std::pow(imu_model.accelSigma(), 2);
  const int64_t frames_per_second = std::max<int64_t>(1, std::llround(opt.cfg.rate));

  try {
    sc.play(
        [&](int64_t i, const ImuReading& r) {
          if (asl) asl->addImu(i, r);
          if (!bag) return;
          const int64_t ns = sc.imuTimeNs(i);
          const ros::Time stamp = stampAt(ns);
          bag->write("/imu/data", stamp, hapi_dataset::toImuMsg(stamp, r.gyro, r.accel, sg2, sa2));
          const double t = ns * 1e-9;
          bag->write("/ground_truth/odometry", stamp, toOdometryMsg(stamp, kWorld, kGt, sc.leftCameraInScene(t)));
          bag->write("/ground_truth/imu_odometry", stamp, toOdometryMsg(stamp, kInertial, kGtImu, sc.imuInInertial(t)));
          if (imaging)
            bag->write("/ground_truth/surface_motion", stamp, toSurfaceMotionMsg(stamp, kImaging, sc.surfaceMotion(t)));
        },
        [&](int64_t k, const cv::Mat& left, const cv::Mat& right) {
          if (asl) asl->addFrame(k, left, right);
          if (bag) {
            const ros::Time stamp = stampAt(sc.frameStampNs(k));
            const ros::Time truth_stamp = stampAt(sc.frameTimeNs(k));
            if (globe && k % frames_per_second == 0)
              bag->write("/globe/info", stamp, globe_info, latchedHeader<std_msgs::String>(kCaller));
            const Pose P = sc.leftCameraInScene(sc.frameTimeNs(k) * 1e-9).pose();
            geometry_msgs::PoseStamped gt;
            gt.header.stamp = truth_stamp;
            gt.header.frame_id = kWorld;
            gt.pose = toPoseMsg(P.p, P.q);
            bag->write("/ground_truth/pose", truth_stamp, gt);
            tf2_msgs::TFMessage tfm;
            tfm.transforms.push_back(toTransformMsg(truth_stamp, kWorld, kGt, P.p, P.q));
            bag->write("/tf", truth_stamp, tfm);
            std_msgs::Header hl, hr;
            hl.stamp = hr.stamp = stamp;
            hl.frame_id = kLeft;
            hr.frame_id = kRight;
            hl.seq = hr.seq = static_cast<uint32_t>(k);
            // Recorded when they arrive: a camera clock offset (--camera-clock-offset)
            // changes the stamps only, as two disagreeing clocks do live.
            const ros::Time arrival =
                stampAt(sc.frameStampNs(k) - std::llround(1e9 * opt.cfg.camera_clock_offset));
            bag->write("/stereo/left/camera_info", arrival, toCameraInfoMsg(ci_l, hl));
            bag->write("/stereo/right/camera_info", arrival, toCameraInfoMsg(ci_r, hr));
            bag->write("/stereo/left/image_raw", arrival, toImageMsg(left, hl));
            bag->write("/stereo/right/image_raw", arrival, toImageMsg(right, hr));
          }
          if ((k + 1) % 10 == 0 || k + 1 == sc.frameCount())
            std::cerr << "[make_sim_bag] frame " << k + 1 << "/" << sc.frameCount() << "\n";
        },
        !imaging ? Scenario::ImagingSink() : [&](int64_t j, const cv::Mat& image) {
          if (asl) asl->addImaging(j, image);
          if (!bag) return;
          const ros::Time stamp = stampAt(sc.imagingStampNs(j));
          std_msgs::Header h;
          h.stamp = stamp;
          h.frame_id = kImaging;
          h.seq = static_cast<uint32_t>(j);
          bag->write("/imaging/camera_info", stamp, toCameraInfoMsg(ci_imaging, h));
          bag->write("/imaging/image_raw", stamp, toImageMsg(image, h));
        });
    if (asl) asl->close();
  } catch (const std::exception& e) {
    std::cerr << "make_sim_bag: " << e.what() << "\n";
    return 1;
  }
  if (bag) bag->close();
  std::cerr << "[make_sim_bag] done:" << (opt.output.empty() ? "" : " " + opt.output)
            << (opt.asl.empty() ? "" : " " + opt.asl) << "\n";
  return 0;
}
