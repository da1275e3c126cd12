#include "surface_conversions.hpp"

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
