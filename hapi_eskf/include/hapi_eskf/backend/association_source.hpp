// What the shared association (association.hpp) needs from a back end: the
// pool's descriptors and the 9x9 marginal covariances of [dp, dtheta, dm_slot]
// (camera pose error of the state's first 6 rows and one landmark). The
// ES-EKF's CovarianceBackend provides both from C; the SEIF's information
// storage from its local inverse; a back end without a covariance backend
// keeps its descriptors in a DescriptorPool (descriptor_pool.hpp) and builds
// the marginals its own way.
#pragma once

#include "hapi_eskf/status.hpp"
#include "hapi_eskf/types.hpp"

#include <cstdint>
#include <vector>

namespace hapi_eskf {

// Best and second-best pool landmark for one query descriptor.
struct DescriptorMatch {
  int best_slot = -1, best_distance = 1 << 30;
  int second_slot = -1, second_distance = 1 << 30;

  // A best match at most max_hamming bits away.
  bool within(int max_hamming) const { return best_slot >= 0 && best_distance <= max_hamming; }
  // The ratio test: the best clearly better than the runner-up (or none).
  bool distinct(double ratio) const { return second_slot < 0 || best_distance < ratio * second_distance; }
};

class AssociationSource {
 public:
  virtual ~AssociationSource() = default;

  // K: landmarks in slots 0..K-1 (the slot order of the back end's map).
  virtual int numLandmarks() const = 0;

  // Hamming best/second-best of n_query descriptors (descriptor length bytes
  // each) against every pool descriptor; out receives n_query matches (slots
  // -1 when there is nothing to compare). kInvalidArgument for a null `out`,
  // a negative n_query or null queries with n_query > 0.
  virtual Status matchDescriptors(const uint8_t* queries, int n_query, std::vector<DescriptorMatch>* out) const = 0;

  // Marginal covariance of [dp, dtheta, dm_slot] (9 x 9) for each slot (a slot
  // may repeat); dp, dtheta are the state's first 6 error rows (the
  // association maps them to the camera with the motion model's Jacobian).
  // kInvalidArgument for a null `out` or a slot outside [0, K).
  virtual Status marginals(const std::vector<int>& slots, std::vector<Mat9>* out) const = 0;
};

}  // namespace hapi_eskf
