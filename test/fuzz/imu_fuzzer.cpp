// libFuzzer target: sensor_msgs/Imu sequences through the back end's IMU
// input as EskfNodelet runs it with motion_model inertial: roscpp
// deserialisation, ImuInput::accept (finite, saturation, clock, frame,
// order, gaps, buffer bound; hapi_eskf/ros/imu_input.hpp), then the worker's
// side: the buffered samples up to each frame go to Eskf::addImu (gravity
// alignment, then the inertial prediction), and a fixed static landmark frame
// every 10 samples runs the update on top of them.
// Input: up to 200 records (bounded_message.hpp), one Imu message each.
#include "bounded_message.hpp"
#include "filter_harness.hpp"

#include "hapi_eskf/ros/imu_input.hpp"
#include "hapi_eskf/ros/params.hpp"
#include "hapi_eskf/ros/statistics.hpp"

#include <sensor_msgs/Imu.h>
#include <tf2_ros/buffer.h>

#include <random>

namespace {

constexpr double kStart = 100.0;  // [s] stamp of the first frame (ros::Time must stay positive)

// 20 points 1-2 m in front of a static camera, ORB-sized random descriptors.
hapi_eskf::StereoFrame staticFrame(double stamp) {
  static const hapi_eskf::StereoFrame base = [] {
    hapi_eskf::StereoFrame f;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    f.descriptor_length = 32;
    for (int i = 0; i < 20; ++i) {
      hapi_eskf::StereoMeasurement m;
      m.z = hapi_eskf::Vec3(u(rng), u(rng), 1.5 + u(rng));
      m.Cz = hapi_eskf::Mat3::Identity() * 1e-6;
      m.frontend_id = static_cast<std::uint32_t>(i);
      m.response = static_cast<float>(100 - i);
      f.measurements.push_back(m);
      for (int b = 0; b < 32; ++b) f.descriptors.push_back(static_cast<std::uint8_t>(rng()));
    }
    return f;
  }();
  hapi_eskf::StereoFrame f = base;
  f.stamp = stamp;
  return f;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hapi_fuzz::quietRosConsole();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hapi_eskf;
  static const tf2_ros::Buffer tf;  // stays empty: the extrinsic is the identity (IMU frame = camera frame)
  ros_glue::NodeletParams params;
  params.filter = hapi_fuzz::fuzzSettings(MotionModelKind::kInertial);
  params.camera_frame = "camera";
  ros_glue::NodeletStatistics stats(true);
  ros_glue::ImuInput input(params, tf, stats, "fuzz");
  hapi_fuzz::FilterUnderTest filter(MotionModelKind::kInertial);

  double frame_stamp = kStart;
  input.onLandmarks("camera", frame_stamp);
  filter.frame(staticFrame(frame_stamp));
  input.dropUpTo(frame_stamp);

  hapi_fuzz::Records records(data, size);
  const std::uint8_t* rec = nullptr;
  std::size_t len = 0;
  int accepted = 0;
  for (int i = 0; i < 200 && records.next(&rec, &len); ++i) {
    sensor_msgs::Imu msg;
    if (!hapi_fuzz::deserialise<sensor_msgs::Imu_>(rec, len, &msg)) continue;
    const std::optional<ros_glue::TimedImuSample> s = input.accept(msg);
    if (!s || ++accepted % 10 != 0) continue;
    // A frame at the newest sample: the worker takes the samples up to it first.
    frame_stamp = s->sample.stamp;
    for (const ros_glue::TimedImuSample& t : input.takeUpTo(frame_stamp)) filter.imu(t.sample);
    filter.frame(staticFrame(frame_stamp));
    input.onLandmarks("camera", frame_stamp);
  }
  return 0;
}
