// Still frames from the bearings of the landmarks two frames share
// (still_frame_detector.hpp).
#include "hapi_eskf/eskf/still_frame_detector.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hapi_eskf {

double StillFrameDetector::apparentSpeed(const Vec3& z_previous, const Vec3& z, double dt) {
  const double range = z.norm();
  if (!(range > 0.0) || !(z_previous.norm() > 0.0) || !(dt > 0.0)) return std::numeric_limits<double>::infinity();
  const double angle = std::atan2(z.cross(z_previous).norm(), z.dot(z_previous));
  return angle * range / dt;
}

StillFrameVerdict StillFrameDetector::test(double stamp, const std::vector<Sighting>& sightings) const {
  StillFrameVerdict v;
  std::vector<double> speed;
  speed.reserve(sightings.size());
  for (const Sighting& s : sightings) {
    const auto it = previous_.find(s.landmark_id);
    if (it != previous_.end()) speed.push_back(apparentSpeed(it->second, s.z, stamp - previous_stamp_));
  }
  v.common = static_cast<int>(speed.size());
  if (v.common < kStillMinCommonLandmarks) return v;
  std::nth_element(speed.begin(), speed.begin() + speed.size() / 2, speed.end());
  v.median_speed = speed[speed.size() / 2];
  v.still = v.median_speed < max_speed_;
  return v;
}

void StillFrameDetector::remember(double stamp, const std::vector<Sighting>& sightings) {
  previous_.clear();
  for (const Sighting& s : sightings) previous_[s.landmark_id] = s.z;
  previous_stamp_ = stamp;
}

}  // namespace hapi_eskf
