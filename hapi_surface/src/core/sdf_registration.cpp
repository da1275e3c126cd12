#include "hapi_surface/sdf_registration.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <vector>

namespace hapi_surface {

bool sampleSignedDistance(const TsdfVolume& volume, const Eigen::Vector3d& p, double* distance,
                          Eigen::Vector3d* gradient) {
  const VoxelGrid& g = volume.grid();
  // Continuous voxel coordinates: samples live at the voxel centres.
  const Eigen::Vector3d q = (p - g.origin) / g.voxel - Eigen::Vector3d::Constant(0.5);
  if (!q.allFinite()) return false;
  const Eigen::Vector3i i0 = q.array().floor().cast<int>();
  for (int a = 0; a < 3; ++a)
    if (i0[a] < 0 || i0[a] + 1 >= g.dims[a]) return false;
  const Eigen::Vector3d f = q - i0.cast<double>();
  const float min_weight = static_cast<float>(volume.settings().mesh_min_weight);
  double c[2][2][2];
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const std::size_t idx = g.index(i0.x() + dx, i0.y() + dy, i0.z() + dz);
        const float t = volume.tsdf()[idx];
        // A clipped sample (|tsdf| = 1) carries no distance, only a side.
        if (volume.weight()[idx] < min_weight || !(std::abs(t) < 0.999f)) return false;
        c[dx][dy][dz] = t;
      }
  // Trilinear value and its derivatives along x, y, z.
  const auto lerp = [](double a, double b, double t) { return a + (b - a) * t; };
  double v[2][2], dvx[2][2];
  for (int dy = 0; dy < 2; ++dy)
    for (int dz = 0; dz < 2; ++dz) {
      v[dy][dz] = lerp(c[0][dy][dz], c[1][dy][dz], f.x());
      dvx[dy][dz] = c[1][dy][dz] - c[0][dy][dz];
    }
  double w[2], dwx[2], dwy[2];
  for (int dz = 0; dz < 2; ++dz) {
    w[dz] = lerp(v[0][dz], v[1][dz], f.y());
    dwx[dz] = lerp(dvx[0][dz], dvx[1][dz], f.y());
    dwy[dz] = v[1][dz] - v[0][dz];
  }
  const double mu = volume.settings().truncation;
  *distance = mu * lerp(w[0], w[1], f.z());
  *gradient = (mu / g.voxel) * Eigen::Vector3d(lerp(dwx[0], dwx[1], f.z()), lerp(dwy[0], dwy[1], f.z()), w[1] - w[0]);
  return true;
}

namespace {

// The frame's depth points (every stride-th pixel) in the camera.
std::vector<Eigen::Vector3d> depthPoints(const DepthFrame& frame, const SurfaceSettings& s) {
  std::vector<Eigen::Vector3d> pts;
  const PinholeCamera& cam = frame.camera;
  for (int v = 0; v < frame.depth.height; v += s.registration_stride)
    for (int u = 0; u < frame.depth.width; u += s.registration_stride) {
      const double d = frame.depth.at(u, v);
      if (!(d >= s.min_depth && d <= s.max_depth)) continue;
      pts.emplace_back(d * (u - cam.cx) / cam.fx, d * (v - cam.cy) / cam.fy, d);
    }
  return pts;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// One Gauss-Newton step of the pose (a rotation about `centre` scaled by
// `length`, then a translation; docs/SURFACE.md eq. R1); the points' |distances| in *abs.
// False without enough points.
bool step(const TsdfVolume& volume, const std::vector<Eigen::Vector3d>& pts_c, const Eigen::Isometry3d& T,
          const Eigen::Vector3d& centre, double length, Eigen::Matrix<double, 6, 1>* delta, std::vector<double>* abs) {
  const SurfaceSettings& s = volume.settings();
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
  abs->clear();
  const double huber = volume.grid().voxel;
  for (const Eigen::Vector3d& pc : pts_c) {
    const Eigen::Vector3d p = T * pc;
    double r;
    Eigen::Vector3d grad;
    if (!sampleSignedDistance(volume, p, &r, &grad)) continue;
    Eigen::Matrix<double, 1, 6> J;
    J.head<3>() = grad.transpose();
    J.tail<3>() = ((p - centre).cross(grad) / length).transpose();
    const double w = std::abs(r) <= huber ? 1.0 : huber / std::abs(r);
    H += w * J.transpose() * J;
    b += w * J.transpose() * r;
    abs->push_back(std::abs(r));
  }
  if (abs->size() < static_cast<std::size_t>(s.registration_min_points)) return false;
  // Solve in the eigenbasis, leaving out the directions the surface does
  // not constrain (eigenvalues below 1e-4 of the largest).
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> es(H);
  const double floor = 1e-4 * es.eigenvalues().maxCoeff();
  Eigen::Matrix<double, 6, 1> x = es.eigenvectors().transpose() * (-b);
  for (int k = 0; k < 6; ++k) x[k] = es.eigenvalues()[k] > floor ? x[k] / es.eigenvalues()[k] : 0.0;
  *delta = es.eigenvectors() * x;
  return true;
}

}  // namespace

Registration registerToSurface(const TsdfVolume& volume, const DepthFrame& frame) {
  const SurfaceSettings& s = volume.settings();
  Registration out;
  out.T_world_camera = frame.T_world_camera;
  const std::vector<Eigen::Vector3d> pts = depthPoints(frame, s);
  if (pts.size() < static_cast<std::size_t>(s.registration_min_points)) return out;
  // Rotations about the points' centroid, in units of their spread, so the
  // six unknowns have comparable scales.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& p : pts) centre += p;
  centre = frame.T_world_camera * (centre / static_cast<double>(pts.size()));
  double length = 0;
  for (const auto& p : pts) length += (frame.T_world_camera * p - centre).norm();
  length = std::max(length / static_cast<double>(pts.size()), 1e-3);

  Eigen::Isometry3d T = frame.T_world_camera;
  std::vector<double> abs;
  Eigen::Matrix<double, 6, 1> delta;
  for (out.iterations = 0; out.iterations < s.registration_iterations; ++out.iterations) {
    if (!step(volume, pts, T, centre, length, &delta, &abs)) return out;
    const Eigen::Vector3d omega = delta.tail<3>() / length;
    Eigen::Isometry3d D = Eigen::Isometry3d::Identity();
    if (omega.norm() > 0) D.linear() = Eigen::AngleAxisd(omega.norm(), omega.normalized()).toRotationMatrix();
    D.translation() = centre - D.linear() * centre + delta.head<3>();
    T = D * T;
    if (delta.norm() < 1e-7) break;
  }
  // Where it ended.
  if (!step(volume, pts, T, centre, length, &delta, &abs)) return out;
  out.T_world_camera = T;
  out.points = abs.size();
  out.median_distance = median(abs);
  out.accepted = out.median_distance <= s.registration_max_residual;
  return out;
}

}  // namespace hapi_surface
