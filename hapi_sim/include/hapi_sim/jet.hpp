// hapi_sim: second-order forward-mode jets in time, and the small 3-vector /
// 3x3-matrix templates the analytic trajectories are written with.
//
// A trajectory is one template function of its scalar: evaluated with double
// it gives the pose, evaluated with Jet2 seeded at (t, 1, 0) it gives the pose
// and its exact first and second time derivatives (no finite differences), so
// velocity, acceleration, angular velocity and angular acceleration are exact
// to rounding (docs/DESIGN.md "Data").
#pragma once
#include <Eigen/Core>
#include <cmath>

namespace hapi_sim {

// f(t), f'(t), f''(t).
struct Jet2 {
  double v = 0.0, d = 0.0, a = 0.0;
  Jet2() = default;
  Jet2(double value) : v(value) {}  // NOLINT: constants promote implicitly
  Jet2(double value, double d1, double d2) : v(value), d(d1), a(d2) {}
  static Jet2 time(double t) { return {t, 1.0, 0.0}; }
};

inline Jet2 operator+(const Jet2& x, const Jet2& y) { return {x.v + y.v, x.d + y.d, x.a + y.a}; }
inline Jet2 operator-(const Jet2& x, const Jet2& y) { return {x.v - y.v, x.d - y.d, x.a - y.a}; }
inline Jet2 operator-(const Jet2& x) { return {-x.v, -x.d, -x.a}; }
inline Jet2 operator*(const Jet2& x, const Jet2& y) {
  return {x.v * y.v, x.d * y.v + x.v * y.d, x.a * y.v + 2.0 * x.d * y.d + x.v * y.a};
}
// Chain rule for a scalar function g with g(x.v) = g0, g'(x.v) = g1, g''(x.v) = g2.
inline Jet2 chain(const Jet2& x, double g0, double g1, double g2) { return {g0, g1 * x.d, g2 * x.d * x.d + g1 * x.a}; }
inline Jet2 inverse(const Jet2& x) { return chain(x, 1.0 / x.v, -1.0 / (x.v * x.v), 2.0 / (x.v * x.v * x.v)); }
inline Jet2 operator/(const Jet2& x, const Jet2& y) { return x * inverse(y); }
inline Jet2& operator+=(Jet2& x, const Jet2& y) { return x = x + y; }
inline Jet2 sin(const Jet2& x) { const double s = std::sin(x.v), c = std::cos(x.v); return chain(x, s, c, -s); }
inline Jet2 cos(const Jet2& x) { const double s = std::sin(x.v), c = std::cos(x.v); return chain(x, c, -s, -c); }
inline Jet2 sqrt(const Jet2& x) {
  const double r = std::sqrt(x.v);
  return chain(x, r, 0.5 / r, -0.25 / (r * x.v));
}

inline double valueOf(double x) { return x; }
inline double valueOf(const Jet2& x) { return x.v; }

template <class T>
struct V3 {
  T x, y, z;
  V3() : x(0.0), y(0.0), z(0.0) {}
  V3(T a, T b, T c) : x(a), y(b), z(c) {}
  explicit V3(const Eigen::Vector3d& e) : x(e.x()), y(e.y()), z(e.z()) {}
  T dot(const V3& o) const { return x * o.x + y * o.y + z * o.z; }
  V3 cross(const V3& o) const { return {y * o.z - z * o.y, z * o.x - x * o.z, x * o.y - y * o.x}; }
  V3 normalized() const {
    using std::sqrt;
    const T inv = T(1.0) / sqrt(dot(*this));
    return {x * inv, y * inv, z * inv};
  }
};
template <class T> V3<T> operator+(const V3<T>& a, const V3<T>& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
template <class T> V3<T> operator-(const V3<T>& a, const V3<T>& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
template <class T> V3<T> operator*(const T& s, const V3<T>& a) { return {s * a.x, s * a.y, s * a.z}; }
inline V3<Jet2> operator*(double s, const V3<Jet2>& a) { return Jet2(s) * a; }

// Rotation matrix by columns (images of the frame's x, y, z axes).
template <class T>
struct M3 {
  V3<T> c0, c1, c2;
  V3<T> operator*(const V3<T>& v) const { return v.x * c0 + v.y * c1 + v.z * c2; }
  M3 operator*(const M3& o) const { return {(*this) * o.c0, (*this) * o.c1, (*this) * o.c2}; }
  static M3 identity() { return {V3<T>(1.0, 0.0, 0.0), V3<T>(0.0, 1.0, 0.0), V3<T>(0.0, 0.0, 1.0)}; }
  M3 transposed() const { return {V3<T>(c0.x, c1.x, c2.x), V3<T>(c0.y, c1.y, c2.y), V3<T>(c0.z, c1.z, c2.z)}; }
};

// Elementary rotations (right-handed, angle in radians).
template <class T> M3<T> rotX(const T& a) {
  using std::cos; using std::sin;
  const T c = cos(a), s = sin(a);
  return {V3<T>(1.0, 0.0, 0.0), V3<T>(0.0, c, s), V3<T>(0.0, -s, c)};
}
template <class T> M3<T> rotY(const T& a) {
  using std::cos; using std::sin;
  const T c = cos(a), s = sin(a);
  return {V3<T>(c, 0.0, -s), V3<T>(0.0, 1.0, 0.0), V3<T>(s, 0.0, c)};
}
template <class T> M3<T> rotZ(const T& a) {
  using std::cos; using std::sin;
  const T c = cos(a), s = sin(a);
  return {V3<T>(c, s, 0.0), V3<T>(-s, c, 0.0), V3<T>(0.0, 0.0, 1.0)};
}

// Optical camera looking from c at target: z forward, x = z x up_hint (image
// right), y = z x x (image down); then rolled by `roll` about the optical axis.
template <class T>
M3<T> lookAt(const V3<T>& c, const V3<T>& target, const V3<T>& up_hint, const T& roll) {
  using std::cos; using std::sin;
  const V3<T> z = (target - c).normalized();
  const V3<T> x0 = z.cross(up_hint).normalized();
  const V3<T> y0 = z.cross(x0);
  const T cr = cos(roll), sr = sin(roll);
  const V3<T> x = cr * x0 + sr * y0;
  return {x, z.cross(x), z};
}

// A pose as a function of time: rotation (body -> reference) and position.
template <class T>
struct PoseT {
  M3<T> R = M3<T>::identity();
  V3<T> p;
  PoseT inverse() const { return {R.transposed(), T(-1.0) * (R.transposed() * p)}; }
  PoseT operator*(const PoseT& o) const { return {R * o.R, p + R * o.p}; }
};

}  // namespace hapi_sim
