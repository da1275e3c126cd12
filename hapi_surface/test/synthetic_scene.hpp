// Analytic scenes for the surface tests and the benchmark: planes, bounded
// plates and spheres, ray cast exactly into depth images (z along the
// optical axis, NaN where nothing is hit) and into images of a value
// pattern painted on the surfaces (through the camera's lens distortion).
#pragma once

#include "hapi_surface/float_image.hpp"
#include "hapi_surface/pinhole_camera.hpp"
#include "hapi_surface/surface_settings.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <functional>
#include <limits>
#include <vector>

namespace hapi_surface {
namespace test {

// The undistorted normalised point of a distorted one, for a camera with
// lens distortion (fixed-point iteration of the plumb_bob model, as
// OpenCV's undistortPoints); the point itself without distortion.
inline Eigen::Vector2d undistort(const PinholeCamera& c, const Eigen::Vector2d& d) {
  Eigen::Vector2d x = d;
  for (int k = 0; c.hasDistortion() && k < 50; ++k) {
    const double r2 = x.squaredNorm();
    const double radial = 1 + r2 * (c.k1 + r2 * (c.k2 + r2 * c.k3));
    const Eigen::Vector2d tangential(2 * c.p1 * x.x() * x.y() + c.p2 * (r2 + 2 * x.x() * x.x()),
                                     c.p1 * (r2 + 2 * x.y() * x.y()) + 2 * c.p2 * x.x() * x.y());
    x = (d - tangential) / radial;
  }
  return x;
}

class Scene {
 public:
  // The plane n . x = d (n unit).
  void addPlane(const Eigen::Vector3d& n, double d) { planes_.push_back({n.normalized(), d}); }
  // The plate z = z0 with x in [x0, x1], y in [y0, y1] (world).
  void addPlate(double z0, double x0, double x1, double y0, double y1) { plates_.push_back({z0, x0, x1, y0, y1}); }
  void addSphere(const Eigen::Vector3d& c, double r) { spheres_.push_back({c, r}); }

  // Smallest t > 0 with o + t dir on a surface; +inf when none.
  double cast(const Eigen::Vector3d& o, const Eigen::Vector3d& dir) const {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& p : planes_) {
      const double den = p.n.dot(dir);
      if (std::abs(den) < 1e-12) continue;
      const double t = (p.d - p.n.dot(o)) / den;
      if (t > 0 && t < best) best = t;
    }
    for (const auto& p : plates_) {
      if (std::abs(dir.z()) < 1e-12) continue;
      const double t = (p.z - o.z()) / dir.z();
      const Eigen::Vector3d x = o + t * dir;
      if (t > 0 && t < best && x.x() >= p.x0 && x.x() <= p.x1 && x.y() >= p.y0 && x.y() <= p.y1) best = t;
    }
    for (const auto& s : spheres_) {
      const Eigen::Vector3d oc = o - s.c;
      const double a = dir.squaredNorm(), b = 2 * oc.dot(dir), c = oc.squaredNorm() - s.r * s.r;
      const double disc = b * b - 4 * a * c;
      if (disc < 0) continue;
      const double t = (-b - std::sqrt(disc)) / (2 * a);
      if (t > 0 && t < best) best = t;
    }
    return best;
  }

  // Depth image (z in the camera) seen by `cam` at `T_wc`.
  FloatImage depth(const PinholeCamera& cam, const Eigen::Isometry3d& T_wc) const {
    return render(cam, T_wc, [](const Eigen::Vector3d&, double z) { return z; });
  }

  // value(p) of the first surface point p seen by each pixel (NaN: none).
  FloatImage pattern(const PinholeCamera& cam, const Eigen::Isometry3d& T_wc,
                     const std::function<double(const Eigen::Vector3d&)>& value) const {
    return render(cam, T_wc, [&](const Eigen::Vector3d& p, double) { return value(p); });
  }

 private:
  FloatImage render(const PinholeCamera& cam, const Eigen::Isometry3d& T_wc,
                    const std::function<double(const Eigen::Vector3d&, double)>& out) const {
    FloatImage im;
    im.width = cam.width;
    im.height = cam.height;
    im.data.resize(static_cast<std::size_t>(cam.width) * cam.height);
    for (int v = 0; v < cam.height; ++v)
      for (int u = 0; u < cam.width; ++u) {
        // A ray whose z component is 1 in the camera: t is the depth.
        const Eigen::Vector2d x = undistort(cam, Eigen::Vector2d((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy));
        const Eigen::Vector3d dc(x.x(), x.y(), 1.0);
        const double t = cast(T_wc.translation(), T_wc.linear() * dc);
        im.at(u, v) = std::isfinite(t) ? static_cast<float>(out(T_wc.translation() + t * (T_wc.linear() * dc), t))
                                       : std::numeric_limits<float>::quiet_NaN();
      }
    return im;
  }

  struct Plane {
    Eigen::Vector3d n;
    double d;
  };
  struct Plate {
    double z, x0, x1, y0, y1;
  };
  struct Sphere {
    Eigen::Vector3d c;
    double r;
  };
  std::vector<Plane> planes_;
  std::vector<Plate> plates_;
  std::vector<Sphere> spheres_;
};

// The default settings with a volume of sx x sy x sz metres (the tests'
// volumes are small, to run fast). The tests' poses are exact from the
// first frame on: no waiting for a settled filter.
inline SurfaceSettings volumeOf(double sx, double sy, double sz) {
  SurfaceSettings s;
  s.settle_time = 0;
  s.volume_size_x = sx;
  s.volume_size_y = sy;
  s.volume_size_z = sz;
  return s;
}

// 640 x 480, 900 px focal length: 0.28 mm per pixel at 25 cm.
inline PinholeCamera testCamera() {
  PinholeCamera c;
  c.width = 640;
  c.height = 480;
  c.fx = c.fy = 900;
  c.cx = 319.5;
  c.cy = 239.5;
  return c;
}

// A camera at `position` looking at `target` (optical z towards it, x roughly along world x).
inline Eigen::Isometry3d lookAt(const Eigen::Vector3d& position, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - position).normalized();
  Eigen::Vector3d x = Eigen::Vector3d::UnitX() - z * z.x();
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = x;
  T.linear().col(1) = y;
  T.linear().col(2) = z;
  T.translation() = position;
  return T;
}

}  // namespace test
}  // namespace hapi_surface
