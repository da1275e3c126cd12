// Full batch refinement and its file output (batch_refinement.hpp).
#include "hapi_eskf/graph/batch_refinement.hpp"

#include "hapi_eskf/backend/map_files.hpp"

#include <algorithm>

namespace hapi_eskf {
namespace graph {

Status refineBatch(const GraphSettings& settings, GraphMap* map, BundleReport* report) {
  if (!map) return Status::kInvalidArgument;
  if (!settings.validate().empty()) return Status::kInvalidArgument;
  std::vector<char> constant(map->keyframes.size(), 0);
  if (!constant.empty()) constant[0] = 1;
  BundleOptions options;
  options.max_iterations = settings.batch_max_iterations;
  options.sparse = true;
  options.covariances = false;
  return adjustBundle(settings, options, constant, map, report);
}

std::string writeGraphFiles(const GraphMap& map, const std::string& ply_path, const std::string& tum_path) {
  std::vector<std::pair<uint64_t, const GraphLandmark*>> sorted;
  for (const auto& kv : map.landmarks) sorted.emplace_back(kv.first, &kv.second);
  std::sort(sorted.begin(), sorted.end());
  std::vector<MapPoint> points;
  for (const auto& s : sorted) {
    MapPoint p;
    p.position = s.second->position;
    p.rgb = s.second->rgb;
    p.sigma = static_cast<float>(landmarkSigma(s.second->covariance));
    p.id = static_cast<uint32_t>(s.first & 0xffffffffu);
    points.push_back(p);
  }
  std::vector<StampedPose> poses;
  if (map.frames.empty()) {
    for (const Keyframe& k : map.keyframes) poses.push_back(StampedPose{k.stamp, k.p, k.q});
  } else {
    for (const FramePose& f : map.frames) {
      const PoseState x = map.framePose(f);
      poses.push_back(StampedPose{f.stamp, x.p, x.q});
    }
  }
  std::string err = writePly(ply_path, points);
  if (err.empty()) err = writeTum(tum_path, poses);
  return err;
}

}  // namespace graph
}  // namespace hapi_eskf
