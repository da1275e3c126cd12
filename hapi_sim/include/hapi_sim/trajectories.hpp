// hapi_sim: the hand-held scenario catalogue: analytic device trajectories
// (left optical frame in the inertial frame) and the scene's own motion
// (scene frame in the inertial frame), all C2 with exact derivatives through
// Jet2. Full parameters: docs/DESIGN.md "Data".
//   smooth    globe: make_globe_bag's orbit; surface: slow scan, no hand motion
//   handheld  slow sweep along the surface + sway (1-3 Hz) + tremor (8-12 Hz)
//   fast      1.7 Hz swipe (>= 1 m/s) + 1 Hz roll (>= 3 rad/s) + tremor
//   loop      leaves the start area (sideways / full orbit) and returns; sway + tremor
//   subject   device held still (tremor only); the scene moves cm and degrees at 0.5-2 Hz
//   rest      device on a stand (no hand motion at all), scene static: the standing-still drift
//   orbit     constant-speed circles around the centre, one in 42 s, no hand motion (loop closure at 42 s)
//   measurement          slow drift and sway with HAPI's measured hand-motion statistics
//                        (kMeasuredHandMotion, 7 s runs) + tremor; scene static
//   measurement_subject  device held still (tremor only); the scene makes the same relative motion
//   stage                device on a stand; the scene translates in its plane at --stage-speed
//                        (still 0.5 s, then a 0.5 s ramp to the constant speed)
//   tremor               device held still (tremor only), scene static: the hand's tremor alone
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hapi_sim/jet.hpp"
#include "hapi_sim/motion.hpp"

namespace hapi_sim {

enum class TrajectoryKind { Smooth, Handheld, Fast, Loop, Subject, Rest, Orbit, Measurement, MeasurementSubject, Stage, Tremor, Calibration };
bool parseTrajectoryKind(const std::string& name, TrajectoryKind* kind);
std::string trajectoryName(TrajectoryKind kind);

// How a scene is framed. The view frame has axes a = along (image right at
// rest), b = up (image up at rest, the look-at up hint) and n = a x b
// (towards the camera); the rest position is centre + standoff * n.
struct ViewGeometry {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d along = Eigen::Vector3d::UnitX();
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  double standoff = 0.25;  // m, camera to centre at rest
  double extent = 0.08;    // m, half-length of a scan along `along`
  bool globe = false;      // smooth = the legacy globe orbit; loop = a full orbit around the centre
  double globe_radius = 0.2;
  Eigen::Vector3d normal() const { return along.cross(up); }
};

// Hand motion: physiological tremor (8-12 Hz, 0.1-0.5 mm, ~0.2-0.5 mrad per
// axis) and sway (1-3 Hz, mm to cm, about a degree per sinusoid): per axis a
// sum of sinusoids whose frequencies, amplitudes and phases come from the seed.
class HandMotion {
 public:
  struct Sinusoid { double amplitude, hz, phase; };
  HandMotion(uint32_t seed, bool tremor, bool sway);
  V3<Jet2> translation(const Jet2& t) const;  // m, added to the camera centre (world axes)
  V3<Jet2> angles(const Jet2& t) const;       // rad, small rotations about the camera's x, y, z
  // The components alone (tests measure their amplitude and frequency).
  const std::vector<Sinusoid>& tremorTranslation(int axis) const { return trem_t_[axis]; }
  const std::vector<Sinusoid>& swayTranslation(int axis) const { return sway_t_[axis]; }
  const std::vector<Sinusoid>& swayRotation(int axis) const { return sway_r_[axis]; }
  static Jet2 evaluate(const std::vector<Sinusoid>& s, const Jet2& t);

 private:
  std::vector<Sinusoid> trem_t_[3], trem_r_[3], sway_t_[3], sway_r_[3];
};

// Camera pose with the hand motion applied: centre + hand translation,
// rotation = R_base * Rz(gz) Ry(gy) Rx(gx) (perturbation in the camera frame).
PoseT<Jet2> applyHand(const PoseT<Jet2>& base, const HandMotion& hand, const Jet2& t);

// The catalogue (one file each).
std::unique_ptr<RigidMotion> makeSmoothTrajectory(const ViewGeometry& view);
std::unique_ptr<RigidMotion> makeHandheldTrajectory(const ViewGeometry& view, uint32_t seed);
std::unique_ptr<RigidMotion> makeFastTrajectory(const ViewGeometry& view, uint32_t seed);
std::unique_ptr<RigidMotion> makeLoopTrajectory(const ViewGeometry& view, uint32_t seed);
std::unique_ptr<RigidMotion> makeOrbitTrajectory(const ViewGeometry& view);
// Calibration: the views a camera calibration needs of a planar target at
// the view centre (trajectory_calibration.cpp).
std::unique_ptr<RigidMotion> makeCalibrationTrajectory(const ViewGeometry& view);
// Subject motion: the device held still (tremor only, no sway; without
// tremor: on a stand) ...
std::unique_ptr<RigidMotion> makeStillTrajectory(const ViewGeometry& view, uint32_t seed, bool tremor = true);
// ... while the scene moves: a few cm and degrees at 0.5-2 Hz about the view centre.
std::unique_ptr<RigidMotion> makeSubjectSceneMotion(const ViewGeometry& view, uint32_t seed);


// HAPI's measured hand motion over a 7 s acquisition: the speed of the
// imaged skin spot over the surface and the device's translation speed
// (m/s). They describe the voluntary motion; tremor (8-12 Hz) comes on top.
struct HandMotionStatistics {
  double surface_mean = 9e-3, surface_max = 17e-3;
  double translation_mean = 6e-3, translation_max = 12e-3;
  double window = 7.0;  // s, the acquisition they were measured over
};
constexpr HandMotionStatistics kMeasuredHandMotion{};

// The measurement scenario: a seeded slow drift and sway about the rest pose
// whose voluntary part has kMeasuredHandMotion's means over its window (the
// spot: the optical axis on the tangent plane at the view's surface point),
// plus tremor unless `tremor` is false (the statistics are of that part).
std::unique_ptr<RigidMotion> makeMeasurementTrajectory(const ViewGeometry& view, uint32_t seed, bool tremor = true);
// ... and the scene motion that gives a device held at the rest pose the
// same voluntary motion relative to the scene (T_IS = T_rest V(t)^-1).
std::unique_ptr<RigidMotion> makeMeasurementSceneMotion(const ViewGeometry& view, uint32_t seed);
// The stage: the scene translates along the view's `along` axis, still for
// kStageStill, then a C2 ramp over kStageRamp to `speed` (m/s), constant after.
constexpr double kStageStill = 0.5, kStageRamp = 0.5;  // s
constexpr double kDefaultStageSpeed = 0.005;             // m/s, the study's middle speed
std::unique_ptr<RigidMotion> makeStageSceneMotion(const ViewGeometry& view, double speed);

// Device motion and scene motion of a scenario (the scene is static except
// for the subject, measurement_subject and stage kinds; stage_speed in m/s).
std::unique_ptr<RigidMotion> makeDeviceMotion(TrajectoryKind kind, const ViewGeometry& view, uint32_t seed);
std::unique_ptr<RigidMotion> makeSceneMotion(TrajectoryKind kind, const ViewGeometry& view, uint32_t seed,
                                             double stage_speed = kDefaultStageSpeed);

}  // namespace hapi_sim
