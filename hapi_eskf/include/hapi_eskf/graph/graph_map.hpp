// The factor graph of Graph SLAM as plain data (docs/DESIGN.md "Graph SLAM"):
// keyframe poses, landmarks, and one stereo point observation per (keyframe,
// landmark) pair. The online back end, its background window solver and the
// full batch refinement all work on this one layout; the per-frame
// trajectory is kept relative to keyframes so a refinement moves it too.
#pragma once

#include "hapi_eskf/types.hpp"

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace hapi_eskf {
namespace graph {

struct Keyframe {
  double stamp = 0.0;
  Vec3 p = Vec3::Zero();                                  // camera position in the world [m]
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  // camera -> world
  // Marginal [dp world, dtheta local] (docs/DESIGN.md "Graph SLAM",
  // covariances): the tracked frame's at creation, then each window solve's
  // while the keyframe is free. Zero: exact (keyframe 0, the gauge).
  Mat6 covariance = Mat6::Zero();
  std::vector<int> observations;                          // indices into GraphMap::observations
};

struct GraphLandmark {
  Vec3 position = Vec3::Zero();    // world [m]
  Mat3 covariance = Mat3::Zero();  // marginal [m^2] (docs/DESIGN.md "Graph SLAM", covariances)
  std::array<uint8_t, 3> rgb{{0, 0, 0}};
  double last_seen = 0.0;
  std::vector<int> observations;   // indices into GraphMap::observations
};

// z = R_k^T (m - p_k) + noise, noise ~ N(0, Cz).
struct Observation {
  int keyframe = 0;
  uint64_t landmark = 0;
  Vec3 z = Vec3::Zero();
  Mat3 Cz = Mat3::Identity();
};

// A processed frame: its pose as the keyframe's pose composed with a fixed
// relative pose, T_world_frame = T_world_keyframe * T_keyframe_frame.
struct FramePose {
  double stamp = 0.0;
  int keyframe = 0;
  Vec3 p_rel = Vec3::Zero();
  Eigen::Quaterniond q_rel = Eigen::Quaterniond::Identity();
};

struct GraphMap {
  std::vector<Keyframe> keyframes;
  std::unordered_map<uint64_t, GraphLandmark> landmarks;
  std::vector<Observation> observations;
  std::vector<FramePose> frames;

  // Appends a keyframe and returns its index.
  int addKeyframe(double stamp, const Vec3& p, const Eigen::Quaterniond& q);
  // Appends an observation of an existing landmark by an existing keyframe.
  void addObservation(int keyframe, uint64_t landmark, const Vec3& z, const Mat3& Cz);
  // Every frame's world pose from its keyframe (the trajectory a refinement moved).
  PoseState framePose(const FramePose& f) const;
};

// Covariance of a landmark given the keyframe poses (poses taken as exact):
// (sum_k R_k Cz_k^-1 R_k^T)^-1 over its observations; a lower bound of the
// marginal (docs/DESIGN.md "Graph SLAM", covariances). Zero without observations.
Mat3 conditionalLandmarkCovariance(const GraphMap& map, const GraphLandmark& landmark);

}  // namespace graph
}  // namespace hapi_eskf
