// One loop around the synthetic globe (globe_scenario.hpp) as a list of
// truth poses and frames, shared by the back-end tests.
#pragma once

#include "globe_scenario.hpp"

#include <vector>

namespace hapi_eskf {
namespace sim {

struct GlobeRun {
  Globe globe;
  std::vector<PoseState> truth;
  std::vector<StereoFrame> frames;
};

// `n_frames` at 10 Hz covering `turns` of the orbit.
inline GlobeRun makeGlobeRun(unsigned seed, int n_points, int n_frames, double turns) {
  std::mt19937 rng(seed);
  GlobeRun r;
  r.globe = makeGlobe(rng, n_points);
  const StereoRig rig = globeRig();
  const double dt = 0.1, rate = 2.0 * M_PI * turns / (n_frames * dt);
  for (int k = 0; k < n_frames; ++k) {
    r.truth.push_back(orbitPose(r.globe, rate * k * dt, rate));
    r.frames.push_back(makeGlobeFrame(r.globe, r.truth.back(), rig, k * dt, rng));
  }
  return r;
}

}  // namespace sim
}  // namespace hapi_eskf
