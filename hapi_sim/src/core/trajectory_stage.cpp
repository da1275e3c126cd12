// The stage: the device stands on a stand (no hand motion) while a motorised
// stage translates the scene in its own plane, along the view's `along`
// axis, as the study's calibration runs do (1, 5 and 10 mm/s). The scene is
// still for kStageStill (the filter starts at rest), then its speed ramps up
// over kStageRamp with the quintic smoothstep (speed and acceleration
// continuous) and stays constant.
#include "hapi_sim/trajectories.hpp"

namespace hapi_sim {
namespace {

class StageMotion : public RigidMotion {
 public:
  StageMotion(const ViewGeometry& v, double speed) : view_(v), speed_(speed) {}
  PoseT<Jet2> evaluate(const Jet2& t) const override {
    PoseT<Jet2> P;
    P.p = Jet2(speed_) * travelTime(t) * V3<Jet2>(view_.along);
    return P;
  }
 private:
  ViewGeometry view_;
  double speed_;

  // Distance travelled at unit speed: 0 before the ramp; over it the integral
  // of s(u) = 10u^3 - 15u^4 + 6u^5 (u the ramp's fraction); then linear.
  static Jet2 travelTime(const Jet2& t) {
    if (t.v <= kStageStill) return Jet2(0.0);
    if (t.v >= kStageStill + kStageRamp) return t - Jet2(kStageStill + 0.5 * kStageRamp);
    const Jet2 u = (t - Jet2(kStageStill)) / Jet2(kStageRamp), u2 = u * u, u4 = u2 * u2;
    return Jet2(kStageRamp) * u4 * (Jet2(2.5) - Jet2(3.0) * u + u2);
  }
};

}  // namespace

std::unique_ptr<RigidMotion> makeStageSceneMotion(const ViewGeometry& view, double speed) {
  return std::make_unique<StageMotion>(view, speed);
}

}  // namespace hapi_sim
