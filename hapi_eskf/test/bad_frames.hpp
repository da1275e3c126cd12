// The bad associated frames every back end must reject without a change
// (associated_frame.hpp checkAssociatedFrame), made from a good frame whose
// first measurement observes a known landmark and which has >= 2 of them.
#pragma once

#include "hapi_eskf/backend/associated_frame.hpp"

#include <cmath>
#include <vector>

namespace hapi_eskf {
namespace sim {

struct BadFrame {
  AssociatedFrame frame;
  Status expected;
  const char* what;
};

inline std::vector<BadFrame> badFrames(const AssociatedFrame& good, double earlier_stamp) {
  std::vector<BadFrame> out;
  AssociatedFrame f = good;
  f.measurements[1].z.x() = std::nan("");
  out.push_back({f, Status::kNonFinite, "NaN z"});
  f = good;
  f.measurements[1].Cz(2, 2) = -1.0;
  out.push_back({f, Status::kNotPositiveDefinite, "non-PD Cz"});
  f = good;
  f.measurements[1].landmark_id = 999999;
  f.measurements[1].is_new = false;
  out.push_back({f, Status::kInvalidArgument, "unknown id"});
  f = good;
  f.measurements[0].is_new = true;
  out.push_back({f, Status::kInvalidArgument, "known id marked new"});
  f = good;
  f.measurements[1].landmark_id = f.measurements[0].landmark_id;
  f.measurements[1].is_new = false;
  out.push_back({f, Status::kDuplicateId, "duplicate id"});
  f = good;
  f.stamp = earlier_stamp;
  out.push_back({f, Status::kInvalidArgument, "stamp going back"});
  return out;
}

}  // namespace sim
}  // namespace hapi_eskf
