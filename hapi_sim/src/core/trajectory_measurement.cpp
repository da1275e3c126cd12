// Measurement: the device moves as HAPI's operators moved it while imaging
// (kMeasuredHandMotion: the imaged spot slides over the skin at 9 mm/s on
// average, 17 mm/s at most; the device translates at 6 mm/s, at most
// 12 mm/s, over a 7 s acquisition), with physiological tremor on top.
//
// The voluntary motion V(t) about the rest pose (docs/DESIGN.md "Data"):
// translation along the view axes a, b (in the surface's plane) and n (the
// stand-off), each a slow drift (one sinusoid of 0.03-0.07 Hz: nearly a
// straight line over 7 s) plus two sway sinusoids of 0.15-0.6 Hz, n at a
// third of the weight; small rotations about the camera's x and y (the aim
// wanders; it moves the spot) and z (roll, a third), two sinusoids of
// 0.1-0.5 Hz each. Frequencies, phases and relative weights come from the
// seed; two scales fix the statistics: the translation scale gives the mean
// translation speed, the rotation scale (bisection) the mean spot speed, the
// spot being where the optical axis meets the tangent plane at the view's
// surface point. Draws whose peaks miss the measured maxima by more than
// kPeakTolerance are drawn again (deterministically, from the same stream).
#include <algorithm>
#include <cmath>
#include <vector>

#include "hapi_sim/trajectories.hpp"

namespace hapi_sim {
namespace {

using Sinusoids = std::vector<HandMotion::Sinusoid>;

constexpr double kSampleStep = 0.01;    // s, the statistics' sampling over the window
constexpr double kPeakTolerance = 0.15;  // relative, of both maxima
constexpr int kMaxDraws = 64;

// Sinusoids of frequencies in [lo, hi] Hz whose rate amplitude (2 pi f A) is
// weight * U(0.5, 1).
Sinusoids drawRates(GaussianRng& rng, int n, double lo, double hi, double weight) {
  Sinusoids s;
  for (int i = 0; i < n; ++i) {
    const double hz = lo + (hi - lo) * rng.uniform01();
    const double rate = weight * (0.5 + 0.5 * rng.uniform01());
    s.push_back({rate / (2 * M_PI * hz), hz, 2 * M_PI * rng.uniform01()});
  }
  return s;
}

struct VoluntaryShape {
  Sinusoids translation[3];  // along a, b, n (m at unit scale)
  Sinusoids rotation[3];     // about the camera's x, y, z (rad at unit scale)
  double kt = 1.0, kr = 1.0;  // the scales
};

VoluntaryShape drawShape(GaussianRng& rng) {
  VoluntaryShape v;
  // Translation along the surface (a), across it (b), the stand-off (n);
  // rotation about the camera's x (aims across), y (along), z (roll).
  const double translation_weight[3] = {1.0, 0.5, 1.0 / 3.0}, rotation_weight[3] = {0.5, 1.0, 1.0 / 3.0};
  for (int k = 0; k < 3; ++k) {
    const double w = translation_weight[k];
    v.translation[k] = drawRates(rng, 1, 0.03, 0.07, 1.5 * w);
    const Sinusoids sway = drawRates(rng, 2, 0.15, 0.6, w);
    v.translation[k].insert(v.translation[k].end(), sway.begin(), sway.end());
    v.rotation[k] = drawRates(rng, 2, 0.1, 0.5, rotation_weight[k]);
  }
  return v;
}

class VoluntaryMotion {
 public:
  VoluntaryMotion(const ViewGeometry& view, uint32_t seed) : view_(view) {
    const V3<Jet2> O(view.centre), b(view.up), n(view.normal());
    rest_.p = O + Jet2(view.standoff) * n;
    rest_.R = lookAt(rest_.p, O, b, Jet2(0.0));
    surface_ = view.globe ? Eigen::Vector3d(view.centre + view.globe_radius * view.normal()) : view.centre;
    GaussianRng rng(mixSeed(seed, 0xFFFFFF07u, 23));
    double best = 0;
    for (int draw = 0; draw < kMaxDraws; ++draw) {
      VoluntaryShape s = drawShape(rng);
      const double miss = normalise(&s);
      if (draw == 0 || miss < best) { best = miss; shape_ = s; }
      if (miss <= kPeakTolerance) break;
    }
  }

  PoseT<Jet2> evaluate(const Jet2& t) const { return at(shape_, t); }
  PoseT<Jet2> rest() const { return rest_; }

 private:
  ViewGeometry view_;
  PoseT<Jet2> rest_;
  Eigen::Vector3d surface_;
  VoluntaryShape shape_;

  PoseT<Jet2> at(const VoluntaryShape& s, const Jet2& t) const {
    const V3<Jet2> a(view_.along), b(view_.up), n(view_.normal());
    // Each sum less its value at t = 0: V(0) is the rest pose.
    auto sum = [&t](const Sinusoids& w, double scale) {
      return Jet2(scale) * (HandMotion::evaluate(w, t) - HandMotion::evaluate(w, Jet2(0.0)));
    };
    PoseT<Jet2> P;
    P.p = rest_.p + sum(s.translation[0], s.kt) * a + sum(s.translation[1], s.kt) * b + sum(s.translation[2], s.kt) * n;
    P.R = rest_.R * (rotZ(sum(s.rotation[2], s.kr)) * (rotY(sum(s.rotation[1], s.kr)) * rotX(sum(s.rotation[0], s.kr))));
    return P;
  }

  // Device speed and spot speed (where the optical axis meets the tangent
  // plane at the surface point) at time t: Y = p + lambda d, lambda such that
  // (Y - S) . n = 0; dY/dt through the jets.
  void speeds(const VoluntaryShape& s, double t, double* device, double* spot) const {
    const PoseT<Jet2> P = at(s, Jet2::time(t));
    *device = std::sqrt(P.p.x.d * P.p.x.d + P.p.y.d * P.p.y.d + P.p.z.d * P.p.z.d);
    const V3<Jet2> n(view_.normal()), S(surface_), d = P.R.c2;
    const Jet2 lambda = (S - P.p).dot(n) / d.dot(n);
    const V3<Jet2> Y = P.p + lambda * d;
    *spot = std::sqrt(Y.x.d * Y.x.d + Y.y.d * Y.y.d + Y.z.d * Y.z.d);
  }

  struct Stats { double device_mean = 0, device_max = 0, spot_mean = 0, spot_max = 0; };
  Stats statistics(const VoluntaryShape& s) const {
    Stats st;
    const int n = static_cast<int>(std::lround(kMeasuredHandMotion.window / kSampleStep));
    for (int i = 0; i <= n; ++i) {
      double dev, spot;
      speeds(s, i * kSampleStep, &dev, &spot);
      st.device_mean += dev / (n + 1);
      st.spot_mean += spot / (n + 1);
      st.device_max = std::max(st.device_max, dev);
      st.spot_max = std::max(st.spot_max, spot);
    }
    return st;
  }

  // Sets the scales so that the means are the measured ones; returns the
  // larger relative miss of the two maxima.
  double normalise(VoluntaryShape* s) const {
    const HandMotionStatistics& m = kMeasuredHandMotion;
    s->kt = 1.0;
    s->kr = 0.0;
    s->kt = m.translation_mean / statistics(*s).device_mean;
    if (statistics(*s).spot_mean >= m.surface_mean) return 1e300;  // translation alone too fast across
    double lo = 0.0, hi = 1e-3;
    while (statistics(withKr(*s, hi)).spot_mean < m.surface_mean && hi < 1e3) hi *= 2;
    for (int it = 0; it < 40; ++it) {
      const double mid = 0.5 * (lo + hi);
      (statistics(withKr(*s, mid)).spot_mean < m.surface_mean ? lo : hi) = mid;
    }
    s->kr = 0.5 * (lo + hi);
    const Stats st = statistics(*s);
    return std::max(std::abs(st.device_max / m.translation_max - 1), std::abs(st.spot_max / m.surface_max - 1));
  }

  static VoluntaryShape withKr(VoluntaryShape s, double kr) {
    s.kr = kr;
    return s;
  }
};

class MeasurementDevice : public RigidMotion {
 public:
  MeasurementDevice(const ViewGeometry& v, uint32_t seed, bool tremor) : motion_(v, seed), hand_(seed, tremor, false) {}
  PoseT<Jet2> evaluate(const Jet2& t) const override { return applyHand(motion_.evaluate(t), hand_, t); }
 private:
  VoluntaryMotion motion_;
  HandMotion hand_;
};

// T_IS(t) = T_rest V(t)^-1: the camera at the rest pose sees the scene as
// the measurement device sees its static scene.
class MeasurementScene : public RigidMotion {
 public:
  MeasurementScene(const ViewGeometry& v, uint32_t seed) : motion_(v, seed) {}
  PoseT<Jet2> evaluate(const Jet2& t) const override { return motion_.rest() * motion_.evaluate(t).inverse(); }
 private:
  VoluntaryMotion motion_;
};

}  // namespace

std::unique_ptr<RigidMotion> makeMeasurementTrajectory(const ViewGeometry& view, uint32_t seed, bool tremor) {
  return std::make_unique<MeasurementDevice>(view, seed, tremor);
}

std::unique_ptr<RigidMotion> makeMeasurementSceneMotion(const ViewGeometry& view, uint32_t seed) {
  return std::make_unique<MeasurementScene>(view, seed);
}

}  // namespace hapi_sim
