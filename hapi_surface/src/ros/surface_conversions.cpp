#include "surface_conversions.hpp"

#include <algorithm>
#include <cmath>

namespace hapi_surface {
namespace ros_glue {

SurfaceStatus toCamera(const sensor_msgs::CameraInfo& info, PinholeCamera* out) {
  PinholeCamera c;
  if (info.width > kMaxImageSide || info.height > kMaxImageSide) return SurfaceStatus::kBadCamera;
  c.width = static_cast<int>(info.width);
  c.height = static_cast<int>(info.height);
  c.fx = info.K[0];
  c.cx = info.K[2];
  c.fy = info.K[4];
  c.cy = info.K[5];
  // plumb_bob: k1 k2 p1 p2 [k3]; rational_polynomial only when its extra
  // terms (k4 k5 k6) are 0, i.e. plumb_bob; no model: no distortion.
  const std::vector<double>& D = info.D;
  const std::string& model = info.distortion_model;
  const bool plumb_bob = model == "plumb_bob" && (D.size() == 4 || D.size() == 5);
  const bool rational = model == "rational_polynomial" && D.size() == 8 && D[5] == 0 && D[6] == 0 && D[7] == 0;
  const bool none = model.empty() && std::all_of(D.begin(), D.end(), [](double d) { return d == 0; });
  if (!plumb_bob && !rational && !none) return SurfaceStatus::kBadCamera;
  if (plumb_bob || rational) {
    c.k1 = D[0];
    c.k2 = D[1];
    c.p1 = D[2];
    c.p2 = D[3];
    c.k3 = D.size() > 4 ? D[4] : 0.0;
  }
  if (c.check() != SurfaceStatus::kOk) return SurfaceStatus::kBadCamera;
  *out = c;
  return SurfaceStatus::kOk;
}

visualization_msgs::Marker toMarker(const Mesh& mesh, const std::vector<Rgb8>& colours, const std::string& frame,
                                    const ros::Time& stamp) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame;
  m.header.stamp = stamp;
  m.ns = "surface";
  m.id = 0;
  m.type = visualization_msgs::Marker::TRIANGLE_LIST;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = 1.0;
  m.color.a = 1.0;
  m.points.reserve(3 * mesh.faces.size());
  m.colors.reserve(3 * mesh.faces.size());
  for (const auto& f : mesh.faces)
    for (int v : f) {
      geometry_msgs::Point p;
      p.x = mesh.vertices[v].x();
      p.y = mesh.vertices[v].y();
      p.z = mesh.vertices[v].z();
      m.points.push_back(p);
      std_msgs::ColorRGBA c;
      c.r = colours[v][0] / 255.f;
      c.g = colours[v][1] / 255.f;
      c.b = colours[v][2] / 255.f;
      c.a = 1.f;
      m.colors.push_back(c);
    }
  return m;
}

}  // namespace ros_glue
}  // namespace hapi_surface
