// Subject motion: the device is held still at the rest position (tremor
// only: a held device is never perfectly still) while the subject moves: the
// scene (arm and table together, or the globe) translates by up to 2 cm and
// rotates by up to 3 degrees at 0.5-2 Hz about the view centre.
#include <cmath>

#include "hapi_sim/trajectories.hpp"

namespace hapi_sim {
namespace {

class StillDevice : public RigidMotion {
 public:
  StillDevice(const ViewGeometry& v, uint32_t seed, bool tremor) : view_(v), hand_(seed, tremor, false) {}
  PoseT<Jet2> evaluate(const Jet2& t) const override {
    const V3<Jet2> O(view_.centre), b(view_.up), n(view_.normal());
    PoseT<Jet2> base;
    base.p = O + Jet2(view_.standoff) * n;
    base.R = lookAt(base.p, O, b, Jet2(0.0));
    return applyHand(base, hand_, t);
  }
 private:
  ViewGeometry view_;
  HandMotion hand_;
};

// T_IS(t) = Trans(O + d(t)) * R(t) * Trans(-O): scene frame in the inertial frame.
class SubjectMotion : public RigidMotion {
 public:
  SubjectMotion(const ViewGeometry& v, uint32_t seed) : view_(v) {
    GaussianRng rng(mixSeed(seed, 0xFFFFFF02u, 9));
    for (double& p : phase_) p = 2 * M_PI * rng.uniform01();
  }
  PoseT<Jet2> evaluate(const Jet2& t) const override {
    const double w = 2 * M_PI, deg = M_PI / 180.0;
    const V3<Jet2> d(Jet2(0.020) * sin(Jet2(w * 0.7) * t + Jet2(phase_[0])),
                     Jet2(0.015) * sin(Jet2(w * 1.1) * t + Jet2(phase_[1])),
                     Jet2(0.006) * sin(Jet2(w * 0.5) * t + Jet2(phase_[2])));
    const Jet2 yaw = Jet2(3.0 * deg) * sin(Jet2(w * 0.6) * t + Jet2(phase_[3]));
    const Jet2 tilt = Jet2(2.0 * deg) * sin(Jet2(w * 1.3) * t + Jet2(phase_[4]));
    const Jet2 roll = Jet2(1.5 * deg) * sin(Jet2(w * 1.9) * t + Jet2(phase_[5]));
    PoseT<Jet2> P;
    P.R = rotZ(yaw) * (rotY(roll) * rotX(tilt));
    const V3<Jet2> O(view_.centre);
    P.p = O + d - P.R * O;
    return P;
  }
 private:
  ViewGeometry view_;
  double phase_[6];
};

}  // namespace

std::unique_ptr<RigidMotion> makeStillTrajectory(const ViewGeometry& view, uint32_t seed, bool tremor) {
  return std::make_unique<StillDevice>(view, seed, tremor);
}

std::unique_ptr<RigidMotion> makeSubjectSceneMotion(const ViewGeometry& view, uint32_t seed) {
  return std::make_unique<SubjectMotion>(view, seed);
}

}  // namespace hapi_sim
