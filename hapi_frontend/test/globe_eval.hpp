// Test/benchmark support: rendered globe stereo pairs (hapi_sim) with ground
// truth, and the front end's accuracy metrics for a StereoFrameResult.
//
// Ground truth of a landmark: the sphere point S hit by the ray of its
// undistorted LEFT pixel. Depth (the dominant error) is then exact; laterally
// S carries the left keypoint's own noise, which in the linearised stereo
// model still gives E[e^T C^-1 e] = 3 (the lateral error (n_r - n_l)/2 has the
// variance the estimator assigns), so S is a fair reference for the NEES too.
// A match is wrong when the left ray misses the globe, S is hidden from the
// right camera, or S projects more than kWrongPx from the right keypoint.
#pragma once

#include "hapi_frontend/stereo_pipeline.hpp"
#include "hapi_sim/globe_sim.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace hapi_frontend {
namespace globe_eval {

constexpr double kWrongPx = 3.0;

struct GlobeWorld {
  hapi_sim::GlobeScene scene = hapi_sim::GlobeScene::makeDefault();
  hapi_sim::StereoRigModel rig = hapi_sim::StereoRigModel::makeDefault();
  hapi_sim::Trajectory traj{scene};
  hapi_sim::Renderer ren_l{scene, rig.left, 2}, ren_r{scene, rig.right, 2};
};

struct GlobePair {
  hapi_sim::Pose T_wl, T_wr;
  cv::Mat left, right;  // mono8, distorted, with 2 grey levels of noise
};

inline GlobePair renderPair(const GlobeWorld& w, double t, uint32_t frame, uint32_t seed = 11) {
  GlobePair p;
  p.T_wl = w.traj.pose(t);
  p.T_wr = w.rig.rightPose(p.T_wl);
  p.left = w.ren_l.render(p.T_wl, hapi_sim::mixSeed(seed, frame, 0), 2.0);
  p.right = w.ren_r.render(p.T_wr, hapi_sim::mixSeed(seed, frame, 1), 2.0);
  return p;
}

struct LandmarkTruth {
  bool hit = false, wrong = true;
  Eigen::Vector3d X_left = Eigen::Vector3d::Zero();  // truth in the left optical frame
  double right_px_err = 1e9;                         // |projection of truth - right keypoint| [px]
  Eigen::Vector2d right_residual = Eigen::Vector2d::Zero();
};

inline LandmarkTruth truthOf(const GlobeWorld& w, const GlobePair& p, const StereoLandmarkOut& lm) {
  LandmarkTruth t;
  const auto& cl = w.rig.left;
  const Eigen::Vector3d ray_c((lm.uv_left.x() - cl.cx) / cl.fx, (lm.uv_left.y() - cl.cy) / cl.fy, 1.0);
  Eigen::Vector3d S;
  if (!w.scene.intersect(p.T_wl.p, (p.T_wl.q * ray_c).normalized(), &S)) return t;
  t.hit = true;
  t.X_left = p.T_wl.q.conjugate() * (S - p.T_wl.p);
  if (!hapi_sim::isVisible(S, p.T_wr, w.scene)) return t;
  const Eigen::Vector3d Xr = p.T_wr.q.conjugate() * (S - p.T_wr.p);
  const auto& cr = w.rig.right;
  const Eigen::Vector2d ur(cr.fx * Xr.x() / Xr.z() + cr.cx, cr.fy * Xr.y() / Xr.z() + cr.cy);
  t.right_residual = lm.uv_right - ur;
  t.right_px_err = t.right_residual.norm();
  t.wrong = !(t.right_px_err <= kWrongPx);
  return t;
}

struct FrameStats {
  int landmarks = 0, wrong = 0;
  std::vector<double> rel_err;  // |x - X| / depth of correct landmarks
  std::vector<double> nees;     // of correct landmarks
};

inline FrameStats evaluate(const GlobeWorld& w, const GlobePair& p, const StereoFrameResult& r) {
  FrameStats s;
  s.landmarks = static_cast<int>(r.landmarks.size());
  for (const auto& lm : r.landmarks) {
    const LandmarkTruth t = truthOf(w, p, lm);
    if (t.wrong) {
      ++s.wrong;
      continue;
    }
    const Eigen::Vector3d e = lm.position - t.X_left;
    s.rel_err.push_back(e.norm() / t.X_left.z());
    s.nees.push_back(e.dot(lm.covariance.ldlt().solve(e)));
  }
  return s;
}

inline double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}
inline double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? NAN : s / v.size();
}

}  // namespace globe_eval
}  // namespace hapi_frontend
