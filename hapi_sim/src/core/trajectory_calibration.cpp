// Calibration: what a person waving a calibration target in front of the
// camera gives the calibrator (cameracalibrator.py's X, Y, size and skew
// bars): the camera looks at the view centre from directions tilted up to
// ~27 deg about both target axes and from 0.5-0.6 x standoff further away,
// the aim point wandering over +-extent. Incommensurate periods (7, 4.6,
// 5.9 and 3.7 s) visit the combinations within a few seconds; no hand
// motion (the calibration's truth is exact views).
#include <cmath>

#include "hapi_sim/trajectories.hpp"

namespace hapi_sim {
namespace {

class CalibrationSweep : public RigidMotion {
 public:
  explicit CalibrationSweep(const ViewGeometry& v) : view_(v) {}
  PoseT<Jet2> evaluate(const Jet2& t) const override {
    const double H = view_.standoff, E = view_.extent;
    const V3<Jet2> O(view_.centre), a(view_.along), b(view_.up), n(view_.normal());
    auto wave = [&t](double period, double phase) { return sin(Jet2(2 * M_PI / period) * t + Jet2(phase)); };
    const Jet2 tilt_a = Jet2(0.5) * wave(7.0, 0.0), tilt_b = Jet2(0.5) * wave(4.6, 1.0);
    const V3<Jet2> aim = O + Jet2(E) * (wave(5.9, 2.0) * a + wave(3.7, 0.5) * b);
    PoseT<Jet2> P;
    P.p = aim + Jet2(H) * (n + tilt_a * a + tilt_b * b);
    P.R = lookAt(P.p, aim, b, Jet2(0.0));
    return P;
  }

 private:
  ViewGeometry view_;
};

}  // namespace

std::unique_ptr<RigidMotion> makeCalibrationTrajectory(const ViewGeometry& view) {
  return std::make_unique<CalibrationSweep>(view);
}

}  // namespace hapi_sim
