// Fast turns: a +-10 cm swipe at 1.7 Hz (peak speed 2 pi 1.7 0.1 = 1.07 m/s)
// and a +-0.6 rad roll about the optical axis at 1 Hz (peak 3.8 rad/s), plus
// tremor. Rolling about the viewing direction and aiming at a point that
// follows half the swipe keep the scene in view at these rates.
#include <cmath>

#include "hapi_sim/trajectories.hpp"

namespace hapi_sim {
namespace {

class FastTurns : public RigidMotion {
 public:
  FastTurns(const ViewGeometry& v, uint32_t seed) : view_(v), hand_(seed, true, false) {}
  PoseT<Jet2> evaluate(const Jet2& t) const override {
    const double w = 2 * M_PI, H = view_.standoff;
    const Jet2 x = Jet2(0.10) * sin(Jet2(w * 1.7) * t);
    const Jet2 y = Jet2(0.2 * view_.extent) * sin(Jet2(w * 0.9) * t);
    const Jet2 roll = Jet2(0.6) * sin(Jet2(w * 1.0) * t);
    const V3<Jet2> O(view_.centre), a(view_.along), b(view_.up), n(view_.normal());
    PoseT<Jet2> base;
    base.p = O + x * a + y * b + Jet2(H) * n;
    base.R = lookAt(base.p, O + Jet2(0.5) * x * a, b, roll);
    return applyHand(base, hand_, t);
  }
 private:
  ViewGeometry view_;
  HandMotion hand_;
};

}  // namespace

std::unique_ptr<RigidMotion> makeFastTrajectory(const ViewGeometry& view, uint32_t seed) {
  return std::make_unique<FastTurns>(view, seed);
}

}  // namespace hapi_sim
