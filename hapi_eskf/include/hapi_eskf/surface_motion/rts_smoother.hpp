// Fixed-interval Rauch-Tung-Striebel smoother over the fusion filter's
// stored steps (docs/DESIGN.md "Surface motion", smoother): backwards from
// the newest step, so each smoothed state uses every measurement up to now.
#pragma once

#include "hapi_eskf/surface_motion/relative_velocity_filter.hpp"

#include <deque>
#include <vector>

namespace hapi_eskf {
namespace surface_motion {

struct SmoothedState {
  double t = 0;
  Vec3 e = Vec3::Zero();
  Mat3 P = Mat3::Zero();
  std::size_t step = 0;  // index in the steps given
};

// The smoothed states of the steps with start <= t <= end, oldest first.
std::vector<SmoothedState> smoothInterval(const std::deque<FilterStep>& steps, double start, double end);

}  // namespace surface_motion
}  // namespace hapi_eskf
