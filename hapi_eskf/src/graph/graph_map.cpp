// Bookkeeping of the factor graph (graph_map.hpp).
#include "hapi_eskf/graph/graph_map.hpp"

#include <Eigen/Cholesky>

namespace hapi_eskf {
namespace graph {

int GraphMap::addKeyframe(double stamp, const Vec3& p, const Eigen::Quaterniond& q) {
  Keyframe k;
  k.stamp = stamp;
  k.p = p;
  k.q = q.normalized();
  keyframes.push_back(k);
  return static_cast<int>(keyframes.size()) - 1;
}

void GraphMap::addObservation(int keyframe, uint64_t landmark, const Vec3& z, const Mat3& Cz) {
  Observation o;
  o.keyframe = keyframe;
  o.landmark = landmark;
  o.z = z;
  o.Cz = Cz;
  const int index = static_cast<int>(observations.size());
  observations.push_back(o);
  keyframes[keyframe].observations.push_back(index);
  landmarks[landmark].observations.push_back(index);
}

PoseState GraphMap::framePose(const FramePose& f) const {
  const Keyframe& k = keyframes[f.keyframe];
  PoseState x;
  x.p = k.p + k.q * f.p_rel;
  x.q = (k.q * f.q_rel).normalized();
  return x;
}

Mat3 conditionalLandmarkCovariance(const GraphMap& map, const GraphLandmark& landmark) {
  Mat3 info = Mat3::Zero();
  for (int i : landmark.observations) {
    const Observation& o = map.observations[i];
    const Mat3 R = map.keyframes[o.keyframe].q.toRotationMatrix();
    info += R * o.Cz.llt().solve(R.transpose());
  }
  if (landmark.observations.empty()) return Mat3::Zero();
  const Mat3 C = info.llt().solve(Mat3::Identity());
  return 0.5 * (C + C.transpose());
}

}  // namespace graph
}  // namespace hapi_eskf
