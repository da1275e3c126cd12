// What a back end on associated frames offers to the shared association and
// bookkeeping (associating_backend.hpp): Graph SLAM (graph/graph_slam.hpp)
// and FastSLAM 2.0 (fastslam/fastslam2.hpp) implement it.
#pragma once

#include "hapi_eskf/backend/associated_frame.hpp"
#include "hapi_eskf/status.hpp"
#include "hapi_eskf/types.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hapi_eskf {

class AssociatedCore {
 public:
  virtual ~AssociatedCore() = default;
  virtual Status reset(const PoseState& initial, double stamp) = 0;
  // One frame (an empty one predicts); a non-kOk status changes nothing.
  virtual Status processAssociated(const AssociatedFrame& frame) = 0;
  // The camera pose predicted to `stamp` and its covariance [dp, dtheta]
  // (no state change): what the association gates against.
  virtual void predicted(double stamp, PoseState* pose, Mat6* covariance) const = 0;
  virtual PoseState pose() const = 0;
  virtual Mat6 poseCovariance() const = 0;  // [dp world, dtheta local]
  virtual std::vector<LandmarkInfo> landmarks() const = 0;
  // The shared bookkeeping evicted these landmarks from the pool: they are
  // observed no more (a core may keep them, e.g. for a refinement).
  virtual void forget(const std::vector<uint64_t>& ids) = 0;
  virtual std::size_t memoryBytes() const = 0;
  // SlamBackend::settle(): waits for background work and merges it.
  virtual void settle() {}
};

}  // namespace hapi_eskf
