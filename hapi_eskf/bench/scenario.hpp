// Synthetic steady-state scenario of the benchmark: a full pool of K
// landmarks, L = 200 of them seen again per frame plus 20 new measurements, so
// association, update, eviction (removal of 20) and addition run every
// iteration. It drives the backend with the filter's own host code
// (backend/measurement_model.hpp, backend/association.hpp) in the order of Eskf::processFrame:
// predict -> association -> update -> removal -> addition -> frameCompleted.
// Which pool landmarks a frame re-observes (Visibility):
//  * kRandom: a random set every frame, i.e. the visible set jumps every frame
//    (the worst case of the partitioned update, and the original scenario);
//  * kSweep: a camera sweeping the map: every landmark has a map coordinate u
//    in [0, 1), the frame sees the `visible` landmarks at or after the cursor
//    (cyclically), and the cursor advances by sweep_step / K per frame, so
//    sweep_step landmarks leave and as many enter the view per frame; new
//    landmarks are placed inside the current view.
#pragma once

#include "hapi_eskf/backend/association.hpp"
#include "hapi_eskf/backend/measurement_model.hpp"
#include "hapi_eskf/backend/pose_kinematics.hpp"
#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "hapi_eskf/settings.hpp"

#include <memory>
#include <random>
#include <string>
#include <vector>

namespace hapi_eskf {
namespace bench {

struct StageTimes {
  double association = 0, removal = 0, addition = 0, predict = 0, update = 0, total = 0;
  // frameCompleted(), the frame's last backend call: starting the work a
  // backend runs between frames (background flush shares), not that work.
  double deferred = 0;
  int n_updated = 0, n_added = 0, n_removed = 0;
  // Landmarks the removal moved into freed slots (removal_plan.hpp): each
  // move copies 3 rows/columns of C, 3 (12 + 3K) elements.
  int removal_moved_landmarks = 0;
  // Flushes of a partitioned backend during this iteration and their time [ms]
  // (included in the stage that triggered them).
  int flushes = 0;
  double flush_ms = 0;
  bool ok = true;
  std::string failure;  // "<stage>: <status>" of the first failed call
};

enum class Visibility { kRandom, kSweep };

class Scenario {
 public:
  static constexpr int kDescLen = 32;
  Scenario(std::unique_ptr<CovarianceBackend> backend, int K, int visible, int fresh, unsigned seed,
           Visibility visibility = Visibility::kRandom, int sweep_step = 10);

  // Fills the pool to K (batched additions; not timed). false on error.
  bool fill();
  // One timed iteration.
  StageTimes iterate();
  const CovarianceBackend& backend() const { return *b_; }

 private:
  std::vector<uint8_t> randomDescriptor();
  NewLandmarkBlock newBlock(const Vec3& z, const std::vector<uint8_t>& d, Vec3* position) const;
  std::vector<int> visibleSlots(int K);

  std::unique_ptr<CovarianceBackend> b_;
  EskfSettings s_;
  int K_, visible_, fresh_;
  std::mt19937 rng_;
  PoseState pose_;
  double t_ = 0;
  std::vector<Vec3> positions_;
  std::vector<std::vector<uint8_t>> desc_;  // host copy, same slot order
  std::vector<double> last_seen_;
  Visibility visibility_;
  int sweep_step_;
  double cursor_ = 0;       // kSweep: map coordinate of the view's start
  std::vector<double> u_;   // kSweep: map coordinate per slot
};

}  // namespace bench
}  // namespace hapi_eskf
