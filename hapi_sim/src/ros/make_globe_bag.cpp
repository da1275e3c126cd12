// make_globe_bag: writes the embedded default data set (a textured globe seen
// by a moving calibrated stereo rig, ground truth, optional IMU) to a rosbag.
//
//   make_globe_bag --output F [--seed N] [--duration S] [--rate HZ] [--imu 0|1]
//                  [--texture PATH] [--noise SIGMA] [--orbit pan|spiral]
// --orbit spiral: the long, non-repeating path of the full-pool soak
// (globe_orbit.hpp globeSpiralPose).
//
// Determinism: every stamp is derived from a fixed epoch (1e9 s) and integer
// nanosecond periods, image noise from the renderer's per-frame seeds
// (mixSeed), IMU noise from one seeded stream; rosbag's C++ writer puts no
// wall-clock time into the file, so the same arguments give a byte-identical
// bag (hapi_sim_bag_test checks it).
//
// Frames (REP-103/105): "world" (z up, the globe's texture frame),
// "stereo_left_optical_frame", "stereo_right_optical_frame" (= left shifted by
// +baseline along x, no rotation), "imu_link" (coincident with the left
// optical frame), and "ground_truth/stereo_left_optical_frame" (the true pose,
// published world -> it on /tf so it never conflicts with an estimator's tree).
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <rosbag/bag.h>
#include <ros/time.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <std_msgs/String.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_msgs/TFMessage.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "hapi_sim/globe_sim.hpp"
#include "bag_messages.hpp"

namespace {

using hapi_sim::CameraInfoData;
using hapi_sim::Pose;
using hapi_sim::stampAt;

using namespace hapi_dataset::recording_frames;

// IMU model (a consumer MEMS part, BMI088-class): white noise densities,
// turn-on bias (constant per seed) and bias random walk.
struct ImuNoise {
  double gyro_density = 1.0e-3;        // rad/s/sqrt(Hz)
  double gyro_bias_sigma = 2.0e-3;     // rad/s, turn-on
  double gyro_walk = 2.0e-5;           // rad/s^2/sqrt(Hz)
  double accel_density = 2.0e-3;       // m/s^2/sqrt(Hz)
  double accel_bias_sigma = 2.0e-2;    // m/s^2, turn-on
  double accel_walk = 3.0e-4;          // m/s^3/sqrt(Hz)
  double gravity = 9.81;               // m/s^2, along -z of the world
};

struct Options {
  std::string output;
  uint32_t seed = 1;
  double duration = 25.0;
  double rate = 10.0;
  bool imu = true;
  double imu_rate = 100.0;
  double noise = 2.0;
  std::string texture = "/usr/share/xplanet/images/earth.jpg";
  hapi_sim::GlobePath orbit = hapi_sim::GlobePath::kPan;
};

[[noreturn]] void usage(const std::string& err) {
  std::cerr << "make_globe_bag: " << err << "\n"
            << "usage: make_globe_bag --output FILE [--seed N] [--duration S] [--rate HZ] [--imu 0|1]\n"
            << "                      [--texture PATH] [--noise SIGMA_GREY] [--orbit pan|spiral]\n";
  std::exit(2);
}

Options parse(int argc, char** argv) {
  using hapi_dataset::parseNumberArg;
  Options o;
  hapi_dataset::forEachOption(argc, argv, usage, [&](const std::string& k, const std::string& v) {
    if (k == "--output") o.output = v;
    else if (k == "--seed") o.seed = static_cast<uint32_t>(hapi_dataset::parseIntegerArg(k, v, 0, 4294967295LL));
    else if (k == "--duration") o.duration = parseNumberArg(k, v);
    else if (k == "--rate") o.rate = parseNumberArg(k, v);
    else if (k == "--imu") o.imu = hapi_dataset::parseFlagArg(k, v);
    else if (k == "--texture") o.texture = v;
    else if (k == "--noise") o.noise = parseNumberArg(k, v);
    else if (k == "--orbit") {
      if (v != "pan" && v != "spiral") usage("--orbit must be pan or spiral");
      o.orbit = v == "spiral" ? hapi_sim::GlobePath::kSpiral : hapi_sim::GlobePath::kPan;
    }
    else usage("unknown option " + k);
  });
  if (o.output.empty()) usage("--output is required");
  if (!(o.duration > 0 && o.duration <= 3600)) usage("--duration must be in (0, 3600] s");
  if (!(o.rate > 0 && o.rate <= 100)) usage("--rate must be in (0, 100] Hz");
  if (!(o.noise >= 0 && o.noise <= 50)) usage("--noise must be in [0, 50] grey levels");
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  const Options opt = parse(argc, argv);
  const hapi_sim::GlobeScene scene = hapi_sim::GlobeScene::makeDefault(opt.texture);
  const hapi_sim::StereoRigModel rig = hapi_sim::StereoRigModel::makeDefault();
  const hapi_sim::Trajectory traj(scene, opt.orbit);
  if (scene.texture_source == "generated")
    std::cerr << "[make_globe_bag] texture '" << opt.texture << "' unreadable: using the generated texture\n";

  const int64_t frame_ns = std::llround(1e9 / opt.rate);
  const int64_t imu_ns = std::llround(1e9 / opt.imu_rate);
  const int64_t n_frames = std::max<int64_t>(1, std::llround(std::floor(opt.duration * opt.rate + 1e-9)));
  const int64_t n_imu = opt.imu ? std::llround(std::floor(opt.duration * opt.imu_rate + 1e-9)) : 0;

  rosbag::Bag bag;
  try {
    bag.open(opt.output, rosbag::bagmode::Write);
  } catch (const rosbag::BagException& e) {
    std::cerr << "make_globe_bag: cannot open '" << opt.output << "' for writing: " << e.what() << "\n";
    return 1;
  }

  std::cerr << "[make_globe_bag] " << opt.output << ": seed " << opt.seed << ", " << n_frames << " stereo frames at "
            << opt.rate << " Hz, IMU " << (opt.imu ? "100 Hz" : "off") << ", texture " << scene.texture_source << "\n";

  const ros::Time t0 = stampAt(0);
  // Static part, once at the start (latched).
  {
    tf2_msgs::TFMessage st;
    st.transforms.push_back(hapi_sim::toTransformMsg(t0, kLeft, kRight, Eigen::Vector3d(rig.baseline, 0, 0), Eigen::Quaterniond::Identity()));
    if (opt.imu) st.transforms.push_back(hapi_sim::toTransformMsg(t0, kLeft, kImu, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity()));
    bag.write("/tf_static", t0, st, hapi_sim::latchedHeader<tf2_msgs::TFMessage>("/make_globe_bag"));
  }
  std_msgs::String info;
  info.data = hapi_sim::globeInfoYaml(scene.radius, scene.centre, kWorld, opt.seed, scene.texture_source);
  const auto info_header = hapi_sim::latchedHeader<std_msgs::String>("/make_globe_bag");

  const hapi_sim::Renderer ren_l(scene, rig.left, 2), ren_r(scene, rig.right, 2);
  const CameraInfoData ci_l = rig.leftInfo(), ci_r = rig.rightInfo();

  // IMU noise state: one seeded stream (camera index 2 of frame 0 is never an image).
  const ImuNoise noise;
  hapi_sim::GaussianRng imu_rng(hapi_sim::mixSeed(opt.seed, 0xFFFFFFFFu, 2));
  Eigen::Vector3d bg, ba;
  for (int i = 0; i < 3; ++i) bg[i] = noise.gyro_bias_sigma * imu_rng.normal();
  for (int i = 0; i < 3; ++i) ba[i] = noise.accel_bias_sigma * imu_rng.normal();
  const double dt_imu = imu_ns * 1e-9;
  const double sg = noise.gyro_density / std::sqrt(dt_imu), sa = noise.accel_density / std::sqrt(dt_imu);

  int64_t next_frame = 0, next_imu = 0;
  while (next_frame < n_frames || next_imu < n_imu) {
    const int64_t tf_ns = next_frame < n_frames ? next_frame * frame_ns : INT64_MAX;
    const int64_t ti_ns = next_imu < n_imu ? next_imu * imu_ns : INT64_MAX;
    if (ti_ns <= tf_ns) {  // IMU first at equal stamps: a filter predicts up to the image time
      const double t = ti_ns * 1e-9;
      const hapi_sim::TrajectorySample s = traj.at(t);
      const Eigen::Matrix3d Rwc = s.T_wc.q.toRotationMatrix();
      // Specific force: f = R^T (a - g), g = (0, 0, -9.81) in the world.
      const Eigen::Vector3d f = Rwc.transpose() * (s.a_w + Eigen::Vector3d(0, 0, noise.gravity));
      sensor_msgs::Imu m;
      m.header.stamp = stampAt(ti_ns);
      m.header.frame_id = kImu;
      m.orientation_covariance[0] = -1.0;  // no orientation estimate (REP-145)
      Eigen::Vector3d w, a;
      for (int i = 0; i < 3; ++i) w[i] = s.omega_c[i] + bg[i] + sg * imu_rng.normal();
      for (int i = 0; i < 3; ++i) a[i] = f[i] + ba[i] + sa * imu_rng.normal();
      tf2::toMsg(w, m.angular_velocity);
      tf2::toMsg(a, m.linear_acceleration);
      for (int i = 0; i < 3; ++i) {
        m.angular_velocity_covariance[4 * i] = sg * sg;
        m.linear_acceleration_covariance[4 * i] = sa * sa;
      }
      bag.write("/imu/data", m.header.stamp, m);
      for (int i = 0; i < 3; ++i) bg[i] += noise.gyro_walk * std::sqrt(dt_imu) * imu_rng.normal();
      for (int i = 0; i < 3; ++i) ba[i] += noise.accel_walk * std::sqrt(dt_imu) * imu_rng.normal();
      ++next_imu;
      continue;
    }
    const int64_t k = next_frame;
    const ros::Time stamp = stampAt(tf_ns);
    const Pose Pl = traj.pose(tf_ns * 1e-9);
    const Pose Pr = rig.rightPose(Pl);

    if (k % std::max<int64_t>(1, std::llround(opt.rate)) == 0)  // 1 Hz, so a late subscriber gets it too
      bag.write("/globe/info", stamp, info, info_header);

    geometry_msgs::PoseStamped gt;
    gt.header.stamp = stamp;
    gt.header.frame_id = kWorld;
    gt.pose = hapi_sim::toPoseMsg(Pl.p, Pl.q);
    bag.write("/ground_truth/pose", stamp, gt);
    tf2_msgs::TFMessage tfm;
    tfm.transforms.push_back(hapi_sim::toTransformMsg(stamp, kWorld, kGt, Pl.p, Pl.q));
    bag.write("/tf", stamp, tfm);

    std_msgs::Header hl, hr;
    hl.stamp = hr.stamp = stamp;
    hl.frame_id = kLeft;
    hr.frame_id = kRight;
    hl.seq = hr.seq = static_cast<uint32_t>(k);
    bag.write("/stereo/left/camera_info", stamp, hapi_sim::toCameraInfoMsg(ci_l, hl));
    bag.write("/stereo/right/camera_info", stamp, hapi_sim::toCameraInfoMsg(ci_r, hr));
    const cv::Mat il = ren_l.render(Pl, hapi_sim::mixSeed(opt.seed, static_cast<uint32_t>(k), 0), opt.noise);
    const cv::Mat ir = ren_r.render(Pr, hapi_sim::mixSeed(opt.seed, static_cast<uint32_t>(k), 1), opt.noise);
    bag.write("/stereo/left/image_raw", stamp, hapi_sim::toImageMsg(il, hl));
    bag.write("/stereo/right/image_raw", stamp, hapi_sim::toImageMsg(ir, hr));
    ++next_frame;
    if (next_frame % 10 == 0 || next_frame == n_frames)
      std::cerr << "[make_globe_bag] frame " << next_frame << "/" << n_frames << "\n";
  }
  bag.close();
  std::cerr << "[make_globe_bag] done: " << opt.output << "\n";
  return 0;
}
