// Whether a frame shows the camera standing still relative to the scene
// (docs/DESIGN.md "Zero-velocity update"). The IMU cannot tell: a
// platform's vibration spreads a standing device's samples 10-20x beyond
// the datasheet noise (EuRoC's MAV on the ground: 0.04 rad/s, 0.5 m/s^2),
// as much as a hand's slow motion. The images can: a landmark seen in two
// consecutive frames keeps its bearing when the camera does not move.
//
// Per frame: for every landmark this frame associated that the previous
// frame also saw, the speed across its ray that would turn its bearing by what it
// turned between the two frames, angle * range / dt; the frame is still
// when the median of those is below still_max_speed over at least
// kStillMinCommonLandmarks landmarks. A speed, not a pixel threshold
// (open_vins's zupt_max_disparity, 0.5 px): the same bearing change is
// 1.5 mm of motion on skin at 30 cm and 1.5 cm on a wall at 3 m.
#pragma once

#include "hapi_eskf/types.hpp"

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace hapi_eskf {

// Fewer landmarks in common than this: no verdict (the median of a handful
// of bearings is one bad keypoint away from either answer).
constexpr int kStillMinCommonLandmarks = 10;

class StillFrameDetector {
 public:
  explicit StillFrameDetector(double max_speed) : max_speed_(max_speed) {}

  // One measurement of a frame: its landmark and where the frame saw it.
  struct Sighting {
    uint64_t landmark_id = 0;
    Vec3 z = Vec3::Zero();  // camera frame [m]
  };
  // This frame's sightings (its associated landmarks) against the
  // previous frame's.
  StillFrameVerdict test(double stamp, const std::vector<Sighting>& sightings) const;
  // The frame's sightings once it is done (associated and started
  // landmarks): the next frame's previous ones.
  void remember(double stamp, const std::vector<Sighting>& sightings);
  // After a reset nothing is compared with the frames before it.
  void reset() {
    previous_.clear();
    previous_stamp_ = 0.0;
  }

  // The speed [m/s] across the ray of z that turns the bearing of
  // z_previous into z's in dt seconds.
  static double apparentSpeed(const Vec3& z_previous, const Vec3& z, double dt);

 private:
  double max_speed_;
  double previous_stamp_ = 0.0;
  std::unordered_map<uint64_t, Vec3> previous_;  // landmark id -> z of the previous frame
};

}  // namespace hapi_eskf
