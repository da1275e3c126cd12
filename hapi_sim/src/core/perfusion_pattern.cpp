// PerfusionPattern and PerfusionRenderer (perfusion_pattern.hpp).
#include "hapi_sim/perfusion_pattern.hpp"

#include <cmath>
#include <sstream>

namespace hapi_sim {

PerfusionPattern PerfusionPattern::forView(const ViewGeometry& view) {
  PerfusionPattern p;
  p.origin = view.centre;
  p.along = view.along.normalized();
  p.up = view.up.normalized();
  // Steps of different heights and both signs of edge direction, spaced so
  // that no two edges lie within 1 cm of each other (an evaluator finds each
  // edge from the values within a few mm of it).
  p.bands = {{0, -0.06, -0.04, 400.0}, {0, 0.02, 0.035, 250.0}, {1, -0.025, -0.012, 150.0}};
  p.discs = {{-0.01, 0.008, 0.012, 300.0}};
  return p;
}

double PerfusionPattern::value(const Eigen::Vector3d& X) const {
  const double s = (X - origin).dot(along), t = (X - origin).dot(up);
  const double k = 2.0 * M_PI / wave_length;
  double v = base + wave_amplitude * std::cos(k * s) * std::cos(k * t);
  for (const Band& b : bands) {
    const double c = b.axis == 0 ? s : t;
    if (c >= b.from && c < b.to) v += b.value;
  }
  for (const Disc& d : discs)
    if ((s - d.s) * (s - d.s) + (t - d.t) * (t - d.t) < d.radius * d.radius) v += d.value;
  return v;
}

std::string PerfusionPattern::yaml() const {
  std::ostringstream o;
  o.precision(9);
  auto vec = [&](const Eigen::Vector3d& v) { o << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]"; };
  o << "unit: PU\norigin: ";
  vec(origin);
  o << "\nalong: ";
  vec(along);
  o << "\nup: ";
  vec(up);
  o << "\nbase: " << base << "\nwave_amplitude: " << wave_amplitude << "\nwave_length: " << wave_length
    << "\nbands:\n";
  for (const Band& b : bands)
    o << "  - {axis: " << (b.axis == 0 ? "s" : "t") << ", from: " << b.from << ", to: " << b.to
      << ", value: " << b.value << "}\n";
  o << "discs:\n";
  for (const Disc& d : discs)
    o << "  - {s: " << d.s << ", t: " << d.t << ", radius: " << d.radius << ", value: " << d.value << "}\n";
  return o.str();
}

PerfusionRenderer::PerfusionRenderer(const Scene& scene, const CameraModel& cam, PerfusionPattern pattern)
    : scene_(scene), cam_(cam), pattern_(std::move(pattern)) {
  rays_.reserve(static_cast<std::size_t>(cam.width) * cam.height);
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) rays_.push_back(pixelToRay(cam, Eigen::Vector2d(u, v)));
}

cv::Mat PerfusionRenderer::render(const Pose& T_sc) const {
  cv::Mat out(cam_.height, cam_.width, CV_32FC1);
  const Eigen::Matrix3d R = T_sc.q.toRotationMatrix();
  for (int v = 0; v < cam_.height; ++v) {
    float* row = out.ptr<float>(v);
    for (int u = 0; u < cam_.width; ++u) {
      const Eigen::Vector3d d = R * rays_[static_cast<std::size_t>(v) * cam_.width + u];
      double t = 0;
      float grey = 0;
      row[u] = scene_.trace(T_sc.p, d, &t, &grey) ? static_cast<float>(pattern_.value(T_sc.p + t * d)) : 0.f;
    }
  }
  return out;
}

}  // namespace hapi_sim
