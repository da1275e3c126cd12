// Synthetic steady-state scenario of the benchmark: a full pool of K
// landmarks, L = 200 of them seen again per frame plus 20 new measurements, so
// association, update, eviction (removal of 20) and addition run every
// iteration. It drives the backend with the filter's own host code
// (jacobians.hpp, association.hpp) in the order of Eskf::processFrame:
// predict -> association -> update -> removal -> addition.
#pragma once

#include "hapi_eskf/association.hpp"
#include "hapi_eskf/covariance_backend.hpp"
#include "hapi_eskf/jacobians.hpp"
#include "hapi_eskf/settings.hpp"

#include <memory>
#include <random>
#include <string>
#include <vector>

namespace hapi_eskf {
namespace bench {

struct StageTimes {
  double association = 0, removal = 0, addition = 0, predict = 0, update = 0, total = 0;
  int n_updated = 0, n_added = 0, n_removed = 0;
  // Landmarks the removal moved into freed slots (removal_plan.hpp): each
  // move copies 3 rows/columns of C, 3 (12 + 3K) elements.
  int removal_moved_landmarks = 0;
  bool ok = true;
  std::string failure;  // "<stage>: <status>" of the first failed call
};

class Scenario {
 public:
  static constexpr int kDescLen = 32;
  Scenario(std::unique_ptr<CovarianceBackend> backend, int K, int visible, int fresh, unsigned seed);

  // Fills the pool to K (batched additions; not timed). false on error.
  bool fill();
  // One timed iteration.
  StageTimes iterate();
  const CovarianceBackend& backend() const { return *b_; }

 private:
  std::vector<uint8_t> randomDescriptor();
  NewLandmarkBlock newBlock(const Vec3& z, const std::vector<uint8_t>& d, Vec3* position) const;

  std::unique_ptr<CovarianceBackend> b_;
  EskfSettings s_;
  int K_, visible_, fresh_;
  std::mt19937 rng_;
  PoseState pose_;
  double t_ = 0;
  std::vector<Vec3> positions_;
  std::vector<std::vector<uint8_t>> desc_;  // host copy, same slot order
  std::vector<double> last_seen_;
};

}  // namespace bench
}  // namespace hapi_eskf
