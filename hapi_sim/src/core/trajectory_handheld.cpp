// Hand-held scan: a slow sweep along the surface (the forearm's axis), 16 s
// period over +-0.8 extent, with the hand's sway and tremor on top.
#include <cmath>

#include "hapi_sim/trajectories.hpp"

namespace hapi_sim {
namespace {

class HandheldScan : public RigidMotion {
 public:
  HandheldScan(const ViewGeometry& v, uint32_t seed) : view_(v), hand_(seed, true, true) {}
  PoseT<Jet2> evaluate(const Jet2& t) const override {
    const double w = 2 * M_PI, E = view_.extent, H = view_.standoff;
    const Jet2 x = Jet2(-0.8 * E) * cos(Jet2(w / 16.0) * t);
    const Jet2 y = Jet2(0.15 * E) * sin(Jet2(w / 11.0) * t);
    const Jet2 h = Jet2(H) * (Jet2(1.0) + Jet2(0.1) * sin(Jet2(w / 8.0) * t + Jet2(1.0)));
    const V3<Jet2> O(view_.centre), a(view_.along), b(view_.up), n(view_.normal());
    PoseT<Jet2> base;
    base.p = O + x * a + y * b + h * n;
    base.R = lookAt(base.p, O + Jet2(0.7) * x * a, b, Jet2(0.0));
    return applyHand(base, hand_, t);
  }
 private:
  ViewGeometry view_;
  HandMotion hand_;
};

}  // namespace

std::unique_ptr<RigidMotion> makeHandheldTrajectory(const ViewGeometry& view, uint32_t seed) {
  return std::make_unique<HandheldScan>(view, seed);
}

}  // namespace hapi_sim
