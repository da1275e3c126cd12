// asl_to_bag: converts an ASL/EuRoC recording (mav0/) into a bag with the
// topics and frames of the simulator's bags, so that launch/replay.launch and
// the evaluator run on it unchanged.
//
//   asl_to_bag --asl DIR --output BAG [--start S] [--duration S] [--rate-divisor N]
//
// DIR is mav0/ or its parent. --start skips S seconds after the first stereo
// frame, --duration keeps S seconds (default: all), --rate-divisor N keeps
// every N-th stereo frame (the IMU and the ground truth are kept whole).
//
// Topics: /stereo/{left,right}/image_raw (mono8, unrectified) and
// camera_info (K, plumb_bob D, R, P of a stereo rectification,
// stereo_calibration.hpp), /imu/data (IMU frame "imu_link"), /tf_static
// (stereo_left_optical_frame -> stereo_right_optical_frame and -> imu_link),
// and with ground truth /ground_truth/pose, /ground_truth/odometry (twist in
// the camera frame) and /tf world -> ground_truth/stereo_left_optical_frame;
// mav0/scene.yaml, when present, latched on /ground_truth/scene
// (std_msgs/String). Frames: docs/DESIGN.md "Dataset calibration".
//
// Determinism: stamps are the dataset's integer nanoseconds, messages are
// written in (stamp, kind) order and rosbag's writer adds no wall time, so the
// same input and options give a byte-identical bag.
#include <cv_bridge/cv_bridge.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/CameraInfo.h>
#include <std_msgs/String.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_msgs/TFMessage.h>

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string>
#include <tuple>
#include <vector>

#include "hapi_dataset/asl_recording.hpp"
#include "hapi_dataset/command_line.hpp"
#include "hapi_dataset/ros/bag_messages.hpp"
#include "hapi_dataset/rig_frames.hpp"
#include "hapi_dataset/stereo_calibration.hpp"

namespace {

using namespace hapi_dataset;

using namespace hapi_dataset::recording_frames;

struct Options {
  std::string asl, output;
  double start = 0.0, duration = -1.0;
  long rate_divisor = 1;
};

[[noreturn]] void usage(const std::string& err) {
  std::cerr << "asl_to_bag: " << err << "\n"
            << "usage: asl_to_bag --asl DIR --output BAG [--start S] [--duration S] [--rate-divisor N]\n";
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  forEachOption(argc, argv, usage, [&](const std::string& k, const std::string& v) {
    if (k == "--asl") o.asl = v;
    else if (k == "--output") o.output = v;
    else if (k == "--start") o.start = parseNumberArg(k, v);
    else if (k == "--duration") o.duration = parseNumberArg(k, v);
    else if (k == "--rate-divisor") o.rate_divisor = static_cast<long>(parseIntegerArg(k, v, 1, 1000));
    else usage("unknown option " + k);
  });
  if (o.asl.empty() || o.output.empty()) usage("--asl and --output are required");
  if (o.start < 0) usage("--start must be >= 0");
  if (o.duration == 0 || o.duration < -1) usage("--duration must be > 0");
  return o;
}

ros::Time stamp(int64_t ns) {
  const SecNsec s = toSecNsec(ns);
  return ros::Time(s.sec, s.nsec);
}

sensor_msgs::ImagePtr loadMono(const std::string& png, const std_msgs::Header& h, const CameraSensor& cam) {
  const cv::Mat img = cv::imread(png, cv::IMREAD_GRAYSCALE);
  if (img.empty()) throw std::runtime_error("cannot read image " + png);
  if (img.cols != cam.width || img.rows != cam.height)
    throw std::runtime_error(png + ": " + std::to_string(img.cols) + "x" + std::to_string(img.rows) +
                             " differs from sensor.yaml's resolution");
  return cv_bridge::CvImage(h, "mono8", img).toImageMsg();
}

geometry_msgs::TransformStamped toTransform(const ros::Time& t, const std::string& parent, const std::string& child,
                                            const Eigen::Isometry3d& T) {
  return toTransformMsg(t, parent, child, T.translation(), Eigen::Quaterniond(T.linear()));
}

// Writing order at equal stamps: IMU first (a filter predicts up to the
// image time), then ground truth, then the stereo frame.
enum Kind { kImuSample = 0, kTruth = 1, kFrame = 2 };
using Event = std::tuple<int64_t, int, size_t>;

}  // namespace

int main(int argc, char** argv) {
  const Options opt = parse(argc, argv);
  AslRecording rec;
  StereoCalibration calib;
  try {
    rec = readAslRecording(opt.asl);
    calib = rectifyStereo(rec.cam0, rec.cam1);
  } catch (const std::exception& e) {
    std::cerr << "asl_to_bag: " << e.what() << "\n";
    return 1;
  }
  const int64_t t_begin = rec.frames.front().stamp_ns + std::llround(opt.start * 1e9);
  const int64_t t_end = opt.duration < 0 ? INT64_MAX : t_begin + std::llround(opt.duration * 1e9);
  const auto inside = [&](int64_t t) { return t >= t_begin && t <= t_end; };

  std::vector<Event> events;
  long kept = 0;
  for (size_t i = 0; i < rec.frames.size(); ++i)
    if (inside(rec.frames[i].stamp_ns) && kept++ % opt.rate_divisor == 0)
      events.emplace_back(rec.frames[i].stamp_ns, kFrame, i);
  if (events.empty()) {
    std::cerr << "asl_to_bag: no stereo frame in the selected window\n";
    return 1;
  }
  for (size_t i = 0; i < rec.imu.size(); ++i)
    if (inside(rec.imu[i].stamp_ns)) events.emplace_back(rec.imu[i].stamp_ns, kImuSample, i);
  if (rec.ground_truth.size() >= 2)
    for (size_t i = 0; i < rec.ground_truth.size(); ++i)
      if (inside(rec.ground_truth[i].stamp_ns)) events.emplace_back(rec.ground_truth[i].stamp_ns, kTruth, i);
  std::sort(events.begin(), events.end());

  rosbag::Bag bag;
  try {
    bag.open(opt.output, rosbag::bagmode::Write);
  } catch (const rosbag::BagException& e) {
    std::cerr << "asl_to_bag: cannot open '" << opt.output << "' for writing: " << e.what() << "\n";
    return 1;
  }
  const ros::Time t0 = stamp(std::get<0>(events.front()));
  {
    tf2_msgs::TFMessage st;
    st.transforms.push_back(toTransform(t0, kLeft, kRight, calib.T_left_right));
    st.transforms.push_back(toTransform(t0, kLeft, kImu, imuInCamera(rec.cam0, rec.imu0)));
    bag.write("/tf_static", t0, st, latchedHeader<tf2_msgs::TFMessage>("/asl_to_bag"));
  }
  if (!rec.scene_yaml.empty()) {
    std_msgs::String scene;
    scene.data = rec.scene_yaml;
    bag.write("/ground_truth/scene", t0, scene, latchedHeader<std_msgs::String>("/asl_to_bag"));
  }
  std::cerr << "[asl_to_bag] " << rec.mav0 << " -> " << opt.output << ": baseline " << calib.baseline << " m, "
            << events.size() << " messages to write\n";

  const double gyro_var = std::pow(rec.imu0.gyroscope_noise_density, 2) * rec.imu0.rate_hz;
  const double accel_var = std::pow(rec.imu0.accelerometer_noise_density, 2) * rec.imu0.rate_hz;
  uint32_t seq = 0;
  try {
    for (const auto& [t_ns, kind, i] : events) {
      const ros::Time t = stamp(t_ns);
      if (kind == kImuSample) {
        // Discrete white-noise variance = density^2 * rate; 0 (unknown) when
        // sensor.yaml states no density.
        const ImuSample& s = rec.imu[i];
        bag.write("/imu/data", t, toImuMsg(t, s.angular_velocity, s.linear_acceleration, gyro_var, accel_var));
      } else if (kind == kTruth) {
        const Eigen::Isometry3d T_W_cam = cameraInWorld(rec.ground_truth[i].T_W_B, rec.cam0);
        geometry_msgs::PoseStamped gt;
        gt.header.stamp = t;
        gt.header.frame_id = kWorld;
        gt.pose = toPoseMsg(T_W_cam.translation(), Eigen::Quaterniond(T_W_cam.linear()));
        bag.write("/ground_truth/pose", t, gt);
        nav_msgs::Odometry odom;
        odom.header = gt.header;
        odom.child_frame_id = kGt;
        odom.pose.pose = gt.pose;
        const CameraTwist tw = cameraTwistAt(rec.ground_truth, i, rec.cam0);
        tf2::toMsg(tw.linear, odom.twist.twist.linear);
        tf2::toMsg(tw.angular, odom.twist.twist.angular);
        bag.write("/ground_truth/odometry", t, odom);
        tf2_msgs::TFMessage tfm;
        tfm.transforms.push_back(toTransform(t, kWorld, kGt, T_W_cam));
        bag.write("/tf", t, tfm);
      } else {
        const StereoFrame& f = rec.frames[i];
        std_msgs::Header hl, hr;
        hl.stamp = hr.stamp = t;
        hl.seq = hr.seq = seq++;
        hl.frame_id = kLeft;
        hr.frame_id = kRight;
        bag.write("/stereo/left/camera_info", t, toCameraInfoMsg(calib.left, hl));
        bag.write("/stereo/right/camera_info", t, toCameraInfoMsg(calib.right, hr));
        bag.write("/stereo/left/image_raw", t, *loadMono(f.left_png, hl, rec.cam0));
        bag.write("/stereo/right/image_raw", t, *loadMono(f.right_png, hr, rec.cam1));
        if (seq % 100 == 0) std::cerr << "[asl_to_bag] frame " << seq << "\n";
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "asl_to_bag: " << e.what() << "\n";
    bag.close();
    return 1;
  }
  bag.close();
  std::cerr << "[asl_to_bag] done: " << seq << " stereo frames, " << opt.output << "\n";
  return 0;
}
