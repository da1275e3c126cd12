// A ROS-free synthetic version of Kock 2021's back-end comparison scenario:
// a stereo camera circling a textured globe once (500 frames at 10 Hz, loop
// closure when the start area comes back into view, from ~frame 420), points
// uniformly on the sphere with random 32-byte descriptors, stereo noise
// (lateral sigma ~ depth, along-ray sigma ~ depth^2), a few descriptor bits
// flipped per observation. Used by compare_backends --synthetic-orbit.
#pragma once

#include "landmark_stream.hpp"

namespace hapi_eskf {
namespace tools {

struct SyntheticOrbitOptions {
  unsigned seed = 1;
  int frames = 500;
  double rate_hz = 10.0;
  double globe_radius = 0.2;      // m
  double orbit_radius = 0.55;     // m, camera to centre
  int points = 6000;              // on the sphere
  int max_measurements = 200;     // per frame (the front end's landmarks_per_frame)
  double focal_px = 700.0, baseline_m = 0.06, sigma_px = 0.5;
  double tan_half_fov = 0.6;
  int bit_flips = 4;
};

LandmarkStream makeSyntheticOrbit(const SyntheticOrbitOptions& o);

}  // namespace tools
}  // namespace hapi_eskf
