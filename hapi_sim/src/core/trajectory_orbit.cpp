// Orbit: the camera circles the view centre at constant speed, once in 42 s,
// without hand motion, so a 50 s run (the back-end comparison scenario of
// Kock 2021: 500 frames at 10 Hz) closes the loop at frame ~420 and then
// goes over the start area again for ~70 degrees. Around the globe it
// keeps the standoff and looks at the centre; over a surface it circles a
// radius of `extent` at the standoff, looking straight down.
#include <cmath>

#include "hapi_sim/trajectories.hpp"

namespace hapi_sim {
namespace {

class Orbit : public RigidMotion {
 public:
  explicit Orbit(const ViewGeometry& v) : view_(v) {}
  PoseT<Jet2> evaluate(const Jet2& t) const override {
    const double H = view_.standoff, E = view_.extent;
    const V3<Jet2> O(view_.centre), a(view_.along), b(view_.up), n(view_.normal());
    const Jet2 phi = Jet2(2 * M_PI / kPeriodS) * t;
    PoseT<Jet2> P;
    if (view_.globe) {
      P.p = O + Jet2(H) * (cos(phi) * n + sin(phi) * a);
      P.R = lookAt(P.p, O, b, Jet2(0.0));
    } else {
      const V3<Jet2> offset = Jet2(E) * ((cos(phi) - Jet2(1.0)) * a + sin(phi) * b);
      P.p = O + offset + Jet2(H) * n;
      P.R = lookAt(P.p, O + offset, b, Jet2(0.0));
    }
    return P;
  }

 private:
  static constexpr double kPeriodS = 42.0;
  ViewGeometry view_;
};

}  // namespace

std::unique_ptr<RigidMotion> makeOrbitTrajectory(const ViewGeometry& view) { return std::make_unique<Orbit>(view); }

}  // namespace hapi_sim
