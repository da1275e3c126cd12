// One FastSLAM 2.0 particle and its per-frame step (docs/DESIGN.md "FastSLAM
// 2.0"): a camera pose, the velocities of its own last step, a log weight,
// and a map of per-landmark 3x3 EKFs. Landmarks are shared between particles
// until one changes them (copy on write), so resampling copies pointers, not
// maps.
#pragma once

#include "hapi_eskf/types.hpp"

#include <memory>
#include <random>
#include <vector>

namespace hapi_eskf {
namespace fastslam {

struct LandmarkEkf {
  Vec3 mean = Vec3::Zero();  // world [m]
  Mat3 cov = Mat3::Zero();
};

struct Particle {
  Vec3 p = Vec3::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  // camera -> world
  Vec3 v = Vec3::Zero();  // world [m/s], from the particle's last step
  Vec3 w = Vec3::Zero();  // camera [rad/s]
  double log_weight = 0.0;
  std::vector<std::shared_ptr<const LandmarkEkf>> map;  // by slot (the filter's id -> slot table)
};

// A measurement of the frame resolved to a slot.
struct SlotMeasurement {
  int slot = 0;
  bool is_new = false;
  Vec3 z = Vec3::Zero();
  Mat3 Cz = Mat3::Identity();
};

// The FastSLAM 2.0 step of one particle over dt: predict with constant
// velocity and process noise Q (6x6, [dp world, dtheta local]), sample the
// pose from the proposal given the known landmarks' measurements, add the
// proposal's marginal log likelihood to the log weight, update those
// landmarks' EKFs at the sampled pose and start the new ones (their slots
// must equal the particle's map size, in order). False when a matrix that
// must be PD is not (the particle is then unchanged).
bool stepParticle(const std::vector<SlotMeasurement>& measurements, double dt, const Mat6& Q, std::mt19937& rng,
                  Particle* particle);

}  // namespace fastslam
}  // namespace hapi_eskf
