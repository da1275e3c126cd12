// Smooth trajectories: the globe's legacy orbit, and for a surface a slow
// C-infinity scan over it (no hand motion): the reference case.
#include <cmath>

#include "hapi_sim/globe_orbit.hpp"
#include "hapi_sim/trajectories.hpp"

namespace hapi_sim {
namespace {

class GlobeOrbit : public RigidMotion {
 public:
  explicit GlobeOrbit(const ViewGeometry& v) : view_(v) {}
  PoseT<Jet2> evaluate(const Jet2& t) const override {
    return globeOrbitPose(t, V3<Jet2>(view_.centre), view_.globe_radius);
  }
 private:
  ViewGeometry view_;
};

// Camera over the surface: along-scan +-0.6 extent (12 s period), across
// +-0.3 extent (9 s), stand-off +-15 % (7 s), looking at a point that follows
// half the along and a third of the across offset, 3 degrees of roll.
class SurfaceScan : public RigidMotion {
 public:
  explicit SurfaceScan(const ViewGeometry& v) : view_(v) {}
  PoseT<Jet2> evaluate(const Jet2& t) const override {
    const double w = 2 * M_PI, E = view_.extent, H = view_.standoff;
    const Jet2 x = Jet2(0.6 * E) * sin(Jet2(w / 12.0) * t);
    const Jet2 y = Jet2(0.3 * E) * sin(Jet2(w / 9.0) * t + Jet2(0.5));
    const Jet2 h = Jet2(H) * (Jet2(1.0) + Jet2(0.15) * sin(Jet2(w / 7.0) * t));
    const V3<Jet2> O(view_.centre), a(view_.along), b(view_.up), n(view_.normal());
    PoseT<Jet2> P;
    P.p = O + x * a + y * b + h * n;
    const V3<Jet2> target = O + Jet2(0.5) * x * a + Jet2(0.3) * y * b;
    P.R = lookAt(P.p, target, b, Jet2(3.0 * M_PI / 180.0) * sin(Jet2(w / 10.0) * t));
    return P;
  }
 private:
  ViewGeometry view_;
};

}  // namespace

std::unique_ptr<RigidMotion> makeSmoothTrajectory(const ViewGeometry& view) {
  if (view.globe) return std::make_unique<GlobeOrbit>(view);
  return std::make_unique<SurfaceScan>(view);
}

}  // namespace hapi_sim
