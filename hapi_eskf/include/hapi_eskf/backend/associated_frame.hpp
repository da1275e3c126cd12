// One frame's stereo measurements after data association: what the back ends
// beside the ES-EKF (Graph SLAM, FastSLAM 2.0) take in. Each measurement
// names the landmark it observes (an id the caller's bookkeeping gave out)
// and says whether that landmark is new, i.e. starts with this observation.
// Frames follow types.hpp: z in the left optical frame, the pose camera ->
// world.
#pragma once

#include "hapi_eskf/status.hpp"
#include "hapi_eskf/types.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace hapi_eskf {

struct AssociatedMeasurement {
  uint64_t landmark_id = 0;  // the landmark observed (a new one gets its id from the caller)
  bool is_new = false;       // true: the landmark starts here and must not be known yet
  Vec3 z = Vec3::Zero();     // camera frame [m]
  Mat3 Cz = Mat3::Identity();  // its covariance [m^2]
  std::array<uint8_t, 3> rgb{{0, 0, 0}};
};

struct AssociatedFrame {
  double stamp = 0.0;  // [s]
  std::vector<AssociatedMeasurement> measurements;
};

// The one input check of every associated-frame back end, run before any
// state changes: kNonFinite (stamp, z or Cz), kNotPositiveDefinite (Cz),
// kDuplicateId (a landmark twice in the frame), kInvalidArgument (stamp
// earlier than `last_stamp`, an id 0, a known landmark marked new or an
// unknown one not marked new). `known(id)` says whether the back end has the
// landmark. An empty frame is kOk: the back ends predict over it.
Status checkAssociatedFrame(const AssociatedFrame& frame, double last_stamp,
                            const std::function<bool(uint64_t)>& known);

}  // namespace hapi_eskf
