// HandMotion: seeded tremor and sway of a hand-held device (docs/DESIGN.md
// "Data"). Physiological tremor of a hand holding a light tool is 8-12 Hz with
// sub-millimetre amplitude; postural sway is 1-3 Hz, millimetres to a
// centimetre and a few degrees.
#include <cmath>

#include "hapi_sim/trajectories.hpp"

namespace hapi_sim {
namespace {

std::vector<HandMotion::Sinusoid> draw(GaussianRng& rng, int n, double amp_lo, double amp_hi, double hz_lo,
                                       double hz_hi) {
  std::vector<HandMotion::Sinusoid> s;
  for (int i = 0; i < n; ++i) {
    const double a = amp_lo + (amp_hi - amp_lo) * rng.uniform01();
    const double f = hz_lo + (hz_hi - hz_lo) * rng.uniform01();
    s.push_back({a, f, 2 * M_PI * rng.uniform01()});
  }
  return s;
}

}  // namespace

HandMotion::HandMotion(uint32_t seed, bool tremor, bool sway) {
  GaussianRng rng(mixSeed(seed, 0xFFFFFF01u, 7));
  constexpr double kMrad = 1e-3, kDeg = M_PI / 180.0;
  for (int k = 0; k < 3; ++k) {
    // Three tremor sinusoids per axis, 0.04-0.10 mm each: the sum peaks
    // between 0.1 and 0.3 mm (test TremorAmplitudeAndFrequency).
    auto tt = draw(rng, 3, 0.04e-3, 0.10e-3, 8.0, 12.0);
    auto tr = draw(rng, 3, 0.1 * kMrad, 0.2 * kMrad, 8.0, 12.0);
    // Two sway sinusoids per axis: 1-4 mm and 0.4-1.2 degrees each.
    auto st = draw(rng, 2, 1.0e-3, 4.0e-3, 1.0, 3.0);
    auto sr = draw(rng, 2, 0.4 * kDeg, 1.2 * kDeg, 1.0, 3.0);
    if (tremor) { trem_t_[k] = tt; trem_r_[k] = tr; }
    if (sway) { sway_t_[k] = st; sway_r_[k] = sr; }
  }
}

Jet2 HandMotion::evaluate(const std::vector<Sinusoid>& s, const Jet2& t) {
  Jet2 sum(0.0);
  for (const Sinusoid& c : s) sum += Jet2(c.amplitude) * sin(Jet2(2 * M_PI * c.hz) * t + Jet2(c.phase));
  return sum;
}

V3<Jet2> HandMotion::translation(const Jet2& t) const {
  return {evaluate(trem_t_[0], t) + evaluate(sway_t_[0], t), evaluate(trem_t_[1], t) + evaluate(sway_t_[1], t),
          evaluate(trem_t_[2], t) + evaluate(sway_t_[2], t)};
}

V3<Jet2> HandMotion::angles(const Jet2& t) const {
  return {evaluate(trem_r_[0], t) + evaluate(sway_r_[0], t), evaluate(trem_r_[1], t) + evaluate(sway_r_[1], t),
          evaluate(trem_r_[2], t) + evaluate(sway_r_[2], t)};
}

PoseT<Jet2> applyHand(const PoseT<Jet2>& base, const HandMotion& hand, const Jet2& t) {
  const V3<Jet2> g = hand.angles(t);
  PoseT<Jet2> P;
  P.R = base.R * (rotZ(g.z) * (rotY(g.y) * rotX(g.x)));
  P.p = base.p + hand.translation(t);
  return P;
}

}  // namespace hapi_sim
