// libFuzzer target: hapi_msgs/ImageFlow bytes through SurfaceMotionNodelet's
// flow path: roscpp deserialisation, the message -> FlowMeasurement
// conversion and SurfaceMotionEstimator::addFlow, between IMU-rate odometry
// samples of a still camera over a plane map (40 ms apart per record,
// from t = 1000 s), then the causal outputs and the smoother over the run.
// Whatever the flows, every OK output must stay finite with a finite
// covariance (a bad flow must not corrupt the filter).
// Input: up to 16 records (bounded_message.hpp), one ImageFlow each.
#include "bounded_message.hpp"
#include "filter_harness.hpp"

#include "surface_motion_conversions.hpp"
#include "surface_motion_scene.hpp"

#include <hapi_msgs/ImageFlow.h>

#include <cstdlib>

namespace {

using namespace hapi_eskf::surface_motion;

bool finiteOutput(const SurfaceMotionOutput& o) {
  if (o.status != MotionStatus::kOk) return true;
  const SurfaceVelocity& v = o.velocity;
  return v.point.allFinite() && v.normal.allFinite() && v.surface_velocity.allFinite() &&
         v.surface_velocity_covariance.allFinite() && std::isfinite(v.normal_velocity) &&
         std::isfinite(v.normal_velocity_variance) && v.image_velocity.allFinite() &&
         v.image_velocity_covariance.allFinite();
}

// A still camera over a plane 0.3 m away: 5 x 5 landmarks 1 cm apart, all
// within the first search radius (few points keep the fuzzer fast).
SurfaceMotionEstimator makeEstimator() {
  SurfaceMotionEstimator est{SurfaceMotionSettings()};
  est.setCamera(test::testCamera());
  std::vector<hapi_eskf::Vec3> map;
  for (int i = -2; i <= 2; ++i)
    for (int j = -2; j <= 2; ++j) map.emplace_back(0.01 * i, 0.01 * j, 0.3);
  est.setMap(std::move(map));
  return est;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hapi_fuzz::quietRosConsole();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  SurfaceMotionEstimator est = makeEstimator();
  double t = 1000.0;
  auto odometry = [&](int steps) {
    for (int k = 0; k < steps; ++k) {
      CameraOdometry o;
      o.t = (t += 0.005);
      const auto out = est.addOdometry(o);
      if (!out || !finiteOutput(*out)) std::abort();
    }
  };
  odometry(8);
  hapi_fuzz::Records records(data, size);
  const std::uint8_t* rec = nullptr;
  std::size_t len = 0;
  for (int i = 0; i < 16 && records.next(&rec, &len); ++i) {
    hapi_msgs::ImageFlow msg;
    if (!hapi_fuzz::deserialise<hapi_msgs::ImageFlow_>(rec, len, &msg)) continue;
    est.addFlow(hapi_eskf::ros_glue::toFlowMeasurement(msg));
    odometry(8);
  }
  for (const SurfaceMotionOutput& o : est.smoothed(0, t))
    if (!finiteOutput(o)) std::abort();
  return 0;
}
