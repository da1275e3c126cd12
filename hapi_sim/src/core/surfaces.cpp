// Geometric primitives of the simulated scenes: ray intersection, exact
// distance to the bounded surfaces, their YAML description, and the bilinear
// texture lookup they are painted with.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "hapi_sim/scene.hpp"
#include "hapi_sim/text_format.hpp"

namespace hapi_sim {
namespace {

std::string num(double v) { return formatNumber(v); }

std::string vec(const Eigen::Vector3d& v) { return "[" + num(v.x()) + ", " + num(v.y()) + ", " + num(v.z()) + "]"; }

}  // namespace

std::string sceneYaml(const std::string& name, const std::vector<SurfaceSpec>& surfaces) {
  std::ostringstream y;
  y << "name: " << name << "\nsurfaces:\n";
  for (const SurfaceSpec& s : surfaces) {
    if (s.type == SurfaceSpec::Sphere)
      y << "  - {type: sphere, centre: " << vec(s.centre) << ", radius: " << num(s.radius) << "}\n";
    else if (s.type == SurfaceSpec::Cylinder)
      y << "  - {type: cylinder, centre: " << vec(s.centre) << ", axis: " << vec(s.axis) << ", radius: " << num(s.radius)
        << ", half_length: " << num(s.half_length) << "}\n";
    else
      y << "  - {type: plane, point: " << vec(s.centre) << ", normal: " << vec(s.axis)
        << ", half_extent: " << num(s.half_extent) << "}\n";
  }
  return y.str();
}

double distanceToSurface(const SurfaceSpec& s, const Eigen::Vector3d& X) {
  const Eigen::Vector3d r = X - s.centre;
  if (s.type == SurfaceSpec::Sphere) return std::abs(r.norm() - s.radius);
  const double along = r.dot(s.axis);
  const Eigen::Vector3d radial = r - along * s.axis;
  const double rho = radial.norm();
  if (s.type == SurfaceSpec::Cylinder) {
    // Nearest point of the open tube: the axial coordinate clamped to the
    // tube, on the circle of that cross-section.
    const double a = std::clamp(along, -s.half_length, s.half_length);
    const double radial_gap = rho - s.radius;
    return std::hypot(along - a, radial_gap);
  }
  // Plane disc: in-plane excess beyond the rim, and the normal offset.
  return std::hypot(std::max(0.0, rho - s.half_extent), along);
}

double distanceToSurfaces(const std::vector<SurfaceSpec>& surfaces, const Eigen::Vector3d& X) {
  double d = std::numeric_limits<double>::infinity();
  for (const SurfaceSpec& s : surfaces) d = std::min(d, distanceToSurface(s, X));
  return d;
}

bool intersectSurface(const SurfaceSpec& s, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double* t) {
  const Eigen::Vector3d oc = o - s.centre;
  if (s.type == SurfaceSpec::Plane) {
    const double dn = d.dot(s.axis);
    if (std::abs(dn) < 1e-12) return false;
    const double tt = -oc.dot(s.axis) / dn;
    if (tt <= 0) return false;
    if ((oc + tt * d).squaredNorm() > s.half_extent * s.half_extent) return false;
    *t = tt;
    return true;
  }
  // Sphere: |oc + t d|^2 = r^2. Cylinder: the same with the axial parts removed.
  Eigen::Vector3d oo = oc, dd = d;
  if (s.type == SurfaceSpec::Cylinder) {
    oo = oc - oc.dot(s.axis) * s.axis;
    dd = d - d.dot(s.axis) * s.axis;
  }
  const double A = dd.squaredNorm();
  if (A < 1e-18) return false;
  const double B = oo.dot(dd), C = oo.squaredNorm() - s.radius * s.radius;
  const double disc = B * B - A * C;
  if (disc < 0) return false;
  const double sq = std::sqrt(disc);
  for (double tt : {(-B - sq) / A, (-B + sq) / A}) {
    if (tt <= 0) continue;
    if (s.type == SurfaceSpec::Cylinder && std::abs((oc + tt * d).dot(s.axis)) > s.half_length) continue;
    *t = tt;
    return true;
  }
  return false;
}

Eigen::Vector3d surfaceNormal(const SurfaceSpec& s, const Eigen::Vector3d& X, const Eigen::Vector3d& d) {
  Eigen::Vector3d n = s.axis;
  if (s.type == SurfaceSpec::Sphere) n = (X - s.centre).normalized();
  if (s.type == SurfaceSpec::Cylinder) {
    const Eigen::Vector3d r = X - s.centre;
    n = (r - r.dot(s.axis) * s.axis).normalized();
  }
  return n.dot(d) < 0 ? n : Eigen::Vector3d(-n);
}

bool intersectSurfaces(const std::vector<SurfaceSpec>& surfaces, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                       double* t, Eigen::Vector3d* normal) {
  const SurfaceSpec* hit = nullptr;
  double best = std::numeric_limits<double>::infinity();
  for (const SurfaceSpec& s : surfaces) {
    double ts;
    if (intersectSurface(s, o, d, &ts) && ts < best) {
      best = ts;
      hit = &s;
    }
  }
  if (!hit) return false;
  *t = best;
  *normal = surfaceNormal(*hit, o + best * d, d);
  return true;
}

float Texture::sample(double u, double v) const {
  const int W = texels.cols, H = texels.rows;
  const double fu = std::floor(u), fv = std::floor(v);
  const float au = static_cast<float>(u - fu), av = static_cast<float>(v - fv);
  int u0 = static_cast<int>(fu), v0 = static_cast<int>(fv), u1 = u0 + 1, v1 = v0 + 1;
  if (wrap_u) {
    u0 = ((u0 % W) + W) % W;
    u1 = ((u1 % W) + W) % W;
  } else {
    u0 = std::clamp(u0, 0, W - 1);
    u1 = std::clamp(u1, 0, W - 1);
  }
  v0 = std::clamp(v0, 0, H - 1);
  v1 = std::clamp(v1, 0, H - 1);
  const float* r0 = texels.ptr<float>(v0);
  const float* r1 = texels.ptr<float>(v1);
  return (1 - av) * ((1 - au) * r0[u0] + au * r0[u1]) + av * ((1 - au) * r1[u0] + au * r1[u1]);
}

}  // namespace hapi_sim
