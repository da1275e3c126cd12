#include "hapi_surface/mesh_depth_render.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hapi_surface {
namespace {

constexpr double kNearPlane = 1e-3;  // m

// Twice the signed area of (a, b, p).
double edge(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  return (b.x() - a.x()) * (p.y() - a.y()) - (b.y() - a.y()) * (p.x() - a.x());
}

}  // namespace

FloatImage renderMeshDepth(const Mesh& mesh, const PinholeCamera& cam, const Eigen::Isometry3d& T_world_camera) {
  FloatImage z;
  z.width = cam.width;
  z.height = cam.height;
  z.data.assign(static_cast<std::size_t>(cam.width) * cam.height, std::numeric_limits<float>::infinity());
  const Eigen::Isometry3d T_cw = T_world_camera.inverse();
  std::vector<Eigen::Vector3d> pc(mesh.vertices.size());
  for (std::size_t i = 0; i < pc.size(); ++i) pc[i] = T_cw * mesh.vertices[i].cast<double>();
  for (const auto& f : mesh.faces) {
    Eigen::Vector2d px[3];
    double inv_z[3];
    bool visible = true;
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d& p = pc[f[c]];
      if (!(p.z() > kNearPlane) || !cam.nearView(p)) visible = false;
      inv_z[c] = 1.0 / p.z();
      // With distortion the triangle's edges are drawn straight between its
      // distorted corners: the mesh's triangles span a few pixels.
      if (visible) px[c] = cam.project(p);
    }
    if (!visible) continue;
    const double area = edge(px[0], px[1], px[2]);
    if (!(std::abs(area) > 1e-12)) continue;
    const int u0 = std::max(0, static_cast<int>(std::ceil(std::min({px[0].x(), px[1].x(), px[2].x()}))));
    const int u1 = std::min(cam.width - 1, static_cast<int>(std::floor(std::max({px[0].x(), px[1].x(), px[2].x()}))));
    const int v0 = std::max(0, static_cast<int>(std::ceil(std::min({px[0].y(), px[1].y(), px[2].y()}))));
    const int v1 = std::min(cam.height - 1, static_cast<int>(std::floor(std::max({px[0].y(), px[1].y(), px[2].y()}))));
    for (int v = v0; v <= v1; ++v)
      for (int u = u0; u <= u1; ++u) {
        const Eigen::Vector2d p(u, v);
        // Barycentric coordinates (either winding).
        const double b0 = edge(px[1], px[2], p) / area, b1 = edge(px[2], px[0], p) / area;
        const double b2 = 1.0 - b0 - b1;
        if (b0 < 0 || b1 < 0 || b2 < 0) continue;
        const float depth = static_cast<float>(1.0 / (b0 * inv_z[0] + b1 * inv_z[1] + b2 * inv_z[2]));
        float& zb = z.at(u, v);
        if (depth < zb) zb = depth;
      }
  }
  return z;
}

}  // namespace hapi_surface
