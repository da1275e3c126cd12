// Loop: leaves the start area and comes back to it (20 s period for a
// surface, 24 s for the globe), with sway and tremor. Over a surface the
// camera slides sideways by up to 2 x 2.2 extent (with the skin framing:
// 35 cm, looking at the table beside the arm, start area out of view);
// around the globe it makes a full orbit (the far side, then home).
#include <cmath>

#include "hapi_sim/trajectories.hpp"

namespace hapi_sim {
namespace {

class Loop : public RigidMotion {
 public:
  Loop(const ViewGeometry& v, uint32_t seed) : view_(v), hand_(seed, true, true) {}
  PoseT<Jet2> evaluate(const Jet2& t) const override {
    const double w = 2 * M_PI, H = view_.standoff;
    const V3<Jet2> O(view_.centre), a(view_.along), b(view_.up), n(view_.normal());
    PoseT<Jet2> base;
    if (view_.globe) {
      const Jet2 phi = Jet2(w / 24.0) * t;
      base.p = O + Jet2(H) * (cos(phi) * n + sin(phi) * a);
      base.R = lookAt(base.p, O, b, Jet2(0.0));
    } else {
      const double L = 2.2 * view_.extent;
      const Jet2 phi = Jet2(w / 20.0) * t;
      const V3<Jet2> offset = Jet2(0.6 * L) * sin(phi) * a + Jet2(L) * (Jet2(1.0) - cos(phi)) * b;
      base.p = O + offset + Jet2(H) * n;
      base.R = lookAt(base.p, O + offset, b, Jet2(0.0));
    }
    return applyHand(base, hand_, t);
  }
 private:
  ViewGeometry view_;
  HandMotion hand_;
};

}  // namespace

std::unique_ptr<RigidMotion> makeLoopTrajectory(const ViewGeometry& view, uint32_t seed) {
  return std::make_unique<Loop>(view, seed);
}

}  // namespace hapi_sim
