// The scenario catalogue by name: which device motion and which scene motion
// each --trajectory means.
#include "hapi_sim/trajectories.hpp"

namespace hapi_sim {
namespace {
const char* const kNames[] = {"smooth", "handheld", "fast",        "loop",                "subject",
                              "rest",   "orbit",    "measurement", "measurement_subject", "stage",
                              "tremor", "calibration"};
constexpr int kCount = sizeof(kNames) / sizeof(kNames[0]);
static_assert(kCount == static_cast<int>(TrajectoryKind::Calibration) + 1, "one name per kind");
}

bool parseTrajectoryKind(const std::string& name, TrajectoryKind* kind) {
  for (int i = 0; i < kCount; ++i)
    if (name == kNames[i]) { *kind = static_cast<TrajectoryKind>(i); return true; }
  return false;
}

std::string trajectoryName(TrajectoryKind kind) { return kNames[static_cast<int>(kind)]; }

std::unique_ptr<RigidMotion> makeDeviceMotion(TrajectoryKind kind, const ViewGeometry& view, uint32_t seed) {
  switch (kind) {
    case TrajectoryKind::Smooth: return makeSmoothTrajectory(view);
    case TrajectoryKind::Handheld: return makeHandheldTrajectory(view, seed);
    case TrajectoryKind::Fast: return makeFastTrajectory(view, seed);
    case TrajectoryKind::Loop: return makeLoopTrajectory(view, seed);
    case TrajectoryKind::Subject: return makeStillTrajectory(view, seed);
    case TrajectoryKind::Rest: return makeStillTrajectory(view, seed, false);
    case TrajectoryKind::Orbit: return makeOrbitTrajectory(view);
    case TrajectoryKind::Measurement: return makeMeasurementTrajectory(view, seed);
    case TrajectoryKind::MeasurementSubject: return makeStillTrajectory(view, seed);
    case TrajectoryKind::Stage: return makeStillTrajectory(view, seed, false);
    case TrajectoryKind::Tremor: return makeStillTrajectory(view, seed);
    case TrajectoryKind::Calibration: return makeCalibrationTrajectory(view);
  }
  return nullptr;
}

std::unique_ptr<RigidMotion> makeSceneMotion(TrajectoryKind kind, const ViewGeometry& view, uint32_t seed,
                                             double stage_speed) {
  if (kind == TrajectoryKind::Subject) return makeSubjectSceneMotion(view, seed);
  if (kind == TrajectoryKind::MeasurementSubject) return makeMeasurementSceneMotion(view, seed);
  if (kind == TrajectoryKind::Stage) return makeStageSceneMotion(view, stage_speed);
  return std::make_unique<StaticMotion>();
}

}  // namespace hapi_sim
