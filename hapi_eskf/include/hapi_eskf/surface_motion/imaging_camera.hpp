// The imaging camera's model (docs/DESIGN.md "Surface motion"): a pinhole
// with K (fx, fy, cx, cy) and optionally plumb_bob distortion (k1, k2, p1,
// p2, k3), as in its CameraInfo; optical frame per REP-103.
#pragma once

#include "hapi_eskf/types.hpp"

#include <array>
#include <string>

namespace hapi_eskf {
namespace surface_motion {

using Vec2 = Eigen::Vector2d;
using Mat2 = Eigen::Matrix2d;
using Mat23 = Eigen::Matrix<double, 2, 3>;

struct ImagingCamera {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::array<double, 5> distortion{{0, 0, 0, 0, 0}};  // plumb_bob k1 k2 p1 p2 k3
  int width = 0, height = 0;
  double frame_rate = 0;  // [Hz]

  // "" when usable, else why not (non-positive focal length, size or rate, NaN).
  std::string check() const;

  // The measurement pixel: (u, v), or the image centre for a coordinate of -1.
  Vec2 pixel(double u, double v) const;

  // Normalised image coordinates (x/z, y/z) of a raw pixel: plumb_bob
  // inverted by fixed-point iteration (a few iterations within the image).
  Vec2 undistort(const Vec2& pixel) const;
  // The unit ray of a raw pixel in the camera frame.
  Vec3 ray(const Vec2& pixel) const;

  // Raw pixel of a point in front of the camera (distortion applied) and its
  // Jacobian d pixel / d X.
  Vec2 project(const Vec3& X) const;
  Mat23 projectJacobian(const Vec3& X) const;

  // The ideal pinhole (no distortion): pixel and Jacobian (the message's
  // image velocity, DESIGN "Surface motion").
  Vec2 projectPinhole(const Vec3& X) const;
  Mat23 pinholeJacobian(const Vec3& X) const;

 private:
  Vec2 distort(const Vec2& xn) const;
  Mat2 distortJacobian(const Vec2& xn) const;
};

}  // namespace surface_motion
}  // namespace hapi_eskf
