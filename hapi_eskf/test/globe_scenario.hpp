// A small synthetic globe stream for the back-end tests: points on a sphere
// with random descriptors, a stereo camera circling it once while looking at
// its centre (constant velocity, so the ES-EKF's motion model is exact), and
// per frame the noisy stereo points of the visible side (sim_scenario.hpp's
// noise model). The world frame is the first camera, as in every back end.
#pragma once

#include "hapi_eskf/backend/associated_frame.hpp"
#include "hapi_eskf/random_draw.hpp"
#include "sim_scenario.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <set>

namespace hapi_eskf {
namespace sim {

struct Globe {
  Vec3 centre = Vec3::Zero();
  double radius = 1.0;
  double orbit = 2.5;  // camera distance from the centre
  World world;
};

inline Globe makeGlobe(std::mt19937& rng, int n_points) {
  Globe g;
  g.centre = Vec3(0, 0, g.orbit);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int i = 0; i < n_points; ++i) {
    g.world.points.push_back(g.centre + g.radius * drawVec3(n01, rng).normalized());
    std::vector<uint8_t> d(32);
    for (auto& b : d) b = static_cast<uint8_t>(byte(rng));
    g.world.descriptors.push_back(d);
  }
  return g;
}

// Camera on the orbit at angle a about the world y axis, looking at the
// centre; a = 0 is the world origin with the identity orientation. v and w
// (camera frame) of a constant angular rate `rate` [rad/s].
inline PoseState orbitPose(const Globe& g, double a, double rate) {
  PoseState x;
  const Vec3 z(std::sin(a), 0.0, std::cos(a)), y(0.0, 1.0, 0.0);
  Mat3 R;
  R << y.cross(z), y, z;
  x.p = g.centre - g.orbit * z;
  x.q = Eigen::Quaterniond(R);
  x.w = Vec3(0.0, rate, 0.0);
  x.v = R.transpose() * (-rate * g.orbit * Vec3(std::cos(a), 0.0, -std::sin(a)));
  return x;
}

inline StereoRig globeRig() {
  StereoRig rig;
  rig.min_depth = 0.5;
  rig.baseline_m = 0.3;
  return rig;
}

// The visible side (incidence below ~70 degrees) inside the rig's view.
inline StereoFrame makeGlobeFrame(const Globe& g, const PoseState& truth, const StereoRig& rig, double stamp,
                                  std::mt19937& rng) {
  World visible;
  std::vector<uint32_t> index;
  for (std::size_t i = 0; i < g.world.points.size(); ++i) {
    const Vec3& X = g.world.points[i];
    const Vec3 n = (X - g.centre).normalized(), ray = (truth.p - X).normalized();
    if (n.dot(ray) < 0.35) continue;
    visible.points.push_back(X);
    visible.descriptors.push_back(g.world.descriptors[i]);
    index.push_back(static_cast<uint32_t>(i));
  }
  StereoFrame f = makeFrame(visible, truth, rig, stamp, 3, rng);
  for (StereoMeasurement& m : f.measurements) m.frontend_id = index[m.frontend_id];
  return f;
}

// Perfect association from the simulation's point index: id = index + 1;
// at most `max_new` unknown points start landmarks, the others are dropped.
inline AssociatedFrame associateByTruth(const StereoFrame& f, int max_new, std::set<uint64_t>* known) {
  AssociatedFrame a;
  a.stamp = f.stamp;
  int added = 0;
  for (const StereoMeasurement& m : f.measurements) {
    AssociatedMeasurement am;
    am.landmark_id = m.frontend_id + 1;
    am.is_new = !known->count(am.landmark_id);
    if (am.is_new && added >= max_new) continue;
    if (am.is_new) {
      ++added;
      known->insert(am.landmark_id);
    }
    am.z = m.z;
    am.Cz = m.Cz;
    am.rgb = m.rgb;
    a.measurements.push_back(am);
  }
  return a;
}

// RMS of the landmarks' distances to the true sphere [m].
inline double sphereRms(const Globe& g, const std::vector<Vec3>& points) {
  double s = 0.0;
  for (const Vec3& m : points) {
    const double d = (m - g.centre).norm() - g.radius;
    s += d * d;
  }
  return points.empty() ? 0.0 : std::sqrt(s / points.size());
}

inline bool isPsd(const Eigen::MatrixXd& C, double tol = 1e-12) {
  if (!C.allFinite() || (C - C.transpose()).cwiseAbs().maxCoeff() > 1e-9 * (1.0 + C.cwiseAbs().maxCoeff()))
    return false;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (C + C.transpose()));
  return es.eigenvalues().minCoeff() >= -tol * (1.0 + es.eigenvalues().cwiseAbs().maxCoeff());
}

}  // namespace sim
}  // namespace hapi_eskf
