// hapi_sim: the globe's smooth orbit/pan (the embedded default data set's
// trajectory), written once as a template of its scalar so that the legacy
// renderer evaluates it in double and the simulation suite in Jet2 (exact
// derivatives).
#pragma once
#include <cmath>

#include "hapi_sim/jet.hpp"

namespace hapi_sim {

// Left optical frame -> world, always looking roughly at the globe centre.
template <class T>
PoseT<T> globeOrbitPose(const T& t, const V3<T>& centre, double radius) {
  using std::cos; using std::sin;
  const double TWO_PI = 2 * M_PI;
  const T dist = T(0.55) + T(0.07) * sin(T(TWO_PI / 13.0) * t);
  const T az = T(-M_PI / 2) + T(0.8) * sin(T(TWO_PI / 24.0) * t) + T(0.1) * sin(T(TWO_PI / 7.0) * t);
  const T el = T(0.3) * sin(T(TWO_PI / 17.0) * t + T(0.4));
  const V3<T> c = centre + dist * V3<T>(cos(el) * cos(az), cos(el) * sin(az), sin(el));
  const V3<T> target = centre + T(0.25 * radius) *
      V3<T>(sin(T(TWO_PI / 9.0) * t), cos(T(TWO_PI / 11.0) * t), T(0.6) * sin(T(TWO_PI / 5.0) * t + T(1.0)));
  const T roll = T(0.12) * sin(T(TWO_PI / 10.0) * t);
  PoseT<T> P;
  P.R = lookAt(c, target, V3<T>(0.0, 0.0, 1.0), roll);
  P.p = c;
  return P;
}

// A slow spiral around the globe for long runs that must keep seeing new
// surface (the full-pool soak, docs/RELIABILITY.md "Full-pool soak"): one
// turn in azimuth every 150 s while the elevation sweeps +-0.9 rad over
// 10 minutes, looking at the surface point below the camera, so a band of
// the globe is seen again only 150 s later, long after the filter's pool
// (a few hundred frames of new landmarks) evicted its landmarks.
template <class T>
PoseT<T> globeSpiralPose(const T& t, const V3<T>& centre, double radius) {
  using std::cos; using std::sin;
  const double TWO_PI = 2 * M_PI;
  const T dist = T(0.55) + T(0.03) * sin(T(TWO_PI / 13.0) * t);
  const T az = T(-M_PI / 2) + T(TWO_PI / 150.0) * t;
  const T el = T(0.9) * sin(T(TWO_PI / 600.0) * t);
  const V3<T> dir(cos(el) * cos(az), cos(el) * sin(az), sin(el));
  const V3<T> c = centre + dist * dir;
  const V3<T> target = centre + T(0.2 * radius) * dir;
  PoseT<T> P;
  P.R = lookAt(c, target, V3<T>(0.0, 0.0, 1.0), T(0.0));
  P.p = c;
  return P;
}

}  // namespace hapi_sim
