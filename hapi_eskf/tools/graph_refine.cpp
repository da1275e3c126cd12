// graph_refine: the full batch refinement of an ES-EKF run (docs/DESIGN.md
// "Graph SLAM", refinement of the filter's stream). Runs the filter over a
// landmark stream (landmark_stream.hpp) exactly as eskf_replay does,
// records its associations and poses as a factor graph (eskf_recording.hpp),
// re-linearises the whole graph with Ceres and writes
//
//   PREFIX_eskf_map.ply, PREFIX_eskf_trajectory.tum   the filter's own map (its final pool) and poses
//   PREFIX_map.ply, PREFIX_trajectory.tum             the refined map (every landmark the filter ever
//                                                     had) and poses
//   PREFIX_map_pool.ply                               the refined map of the filter's final pool only
//                                                     (the like-for-like comparison)
//   PREFIX_truth.tum, PREFIX_scene.yaml               the stream's ground truth and scene, when it has them
//
// in the formats of map_files.hpp, for tools/eval/evaluate.py (--map, --scene).
//
//   graph_refine STREAM --out PREFIX [key=value ...] [graph.key=value ...]
//
// key=value sets a filter setting (eskf_replay --help lists them),
// graph.key=value a Graph SLAM setting (graph_settings.def; --help).
#include "hapi_eskf/backend/map_files.hpp"
#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "hapi_eskf/eskf/eskf.hpp"
#include "hapi_eskf/eskf/storage_factory.hpp"
#include "hapi_eskf/graph/batch_refinement.hpp"
#include "hapi_eskf/graph/eskf_recording.hpp"
#include "landmark_stream.hpp"

#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

using namespace hapi_eskf;

namespace {

std::vector<MapPoint> toPoints(const std::vector<LandmarkInfo>& landmarks) {
  std::vector<MapPoint> out;
  for (const LandmarkInfo& l : landmarks) {
    MapPoint p;
    p.position = l.position;
    p.rgb = l.rgb;
    p.sigma = static_cast<float>(landmarkSigma(l.covariance));
    p.id = static_cast<uint32_t>(l.id & 0xffffffffu);
    out.push_back(p);
  }
  return out;
}

bool report(const std::string& err) {
  if (!err.empty()) std::cerr << err << "\n";
  return err.empty();
}

}  // namespace

int main(int argc, char** argv) {
  const char* usage = "usage: graph_refine STREAM --out PREFIX [key=value ...] [graph.key=value ...]\n";
  if (argc >= 2 && std::string(argv[1]) == "--help") {
    std::cout << usage << "filter settings (key=value):\n";
    const EskfSettings filter_defaults;
    forEachField(filter_defaults,
                 [](const FieldInfo& f, const auto& v) { std::cout << "  " << describeField(f, v) << "\n"; });
    std::cout << "Graph SLAM settings (graph.key=value):\n";
    const graph::GraphSettings graph_defaults;
    forEachField(graph_defaults,
                 [](const FieldInfo& f, const auto& v) { std::cout << "  graph." << describeField(f, v) << "\n"; });
    return 0;
  }
  if (argc < 2) {
    std::cerr << usage;
    return 1;
  }
  EskfSettings s;
  graph::GraphSettings gs;
  std::string prefix;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--out" && i + 1 < argc) {
      prefix = argv[++i];
      continue;
    }
    const auto eq = a.find('=');
    if (eq == std::string::npos) {
      std::cerr << "unknown argument " << a << "\n" << usage;
      return 1;
    }
    const std::string key = a.substr(0, eq), value = a.substr(eq + 1);
    const std::string err = key.rfind("graph.", 0) == 0 ? graph::setFieldFromText(&gs, key.substr(6), value)
                                                        : setFieldFromText(&s, key, value);
    if (!err.empty()) {
      std::cerr << err << " (graph_refine --help lists the settings)\n";
      return 1;
    }
  }
  if (prefix.empty()) {
    std::cerr << usage;
    return 1;
  }
  for (const std::string& err : {s.validate(), gs.validate()})
    if (!err.empty()) {
      std::cerr << err << "\n";
      return 1;
    }

  tools::LandmarkStream stream;
  std::string err;
  if (!tools::readLandmarkStream(argv[1], &stream, &err)) {
    std::cerr << err << "\n";
    return 1;
  }
  if (stream.frames.empty()) {
    std::cerr << "no frames in " << argv[1] << "\n";
    return 1;
  }
  const bool use_imu = s.motion_model != MotionModelKind::kConstantVelocity;
  if (use_imu && (stream.imu.empty() || !stream.extrinsic)) {
    std::cerr << "motion_model " << toString(s.motion_model) << " needs IMU samples and an extrinsic in the stream\n";
    return 1;
  }
  auto backend = makeBackend(s, stream.frames[0].descriptor_length, &err);
  if (!backend) {
    std::cerr << err << "\n";
    return 1;
  }
  Eskf eskf(s, std::move(backend), stream.extrinsic.value_or(CameraExtrinsic()));
  eskf.reset(PoseState(), stream.frames[0].stamp);

  // The filter as eskf_replay runs it: every IMU sample up to a frame's stamp first.
  std::vector<ImuSample> imu;
  for (const ImuSample& m : stream.imu) imu.push_back(imuSampleOnCameraClock(m.stamp, m.gyro, m.accel, s));
  std::size_t next_imu = 0;
  graph::EskfRecorder recorder(gs.keyframe_min_observations);
  std::vector<StampedPose> eskf_poses;
  int rejected = 0;
  for (const StereoFrame& f : stream.frames) {
    for (; use_imu && next_imu < imu.size() && imu[next_imu].stamp <= f.stamp; ++next_imu)
      if (imu[next_imu].stamp > eskf.time()) eskf.addImu(imu[next_imu]);
    IterationReport rep;
    const Status st = recorder.processFrame(&eskf, f, &rep);
    if (st == Status::kAwaitingImu || rep.relocalising) continue;
    if (st != Status::kOk && st != Status::kNotPositiveDefinite) {
      ++rejected;
      continue;
    }
    eskf_poses.push_back(StampedPose{f.stamp, eskf.pose().p, eskf.pose().q});
  }
  const std::vector<LandmarkInfo> pool = eskf.landmarks();
  if (!report(writePly(prefix + "_eskf_map.ply", toPoints(pool))) ||
      !report(writeTum(prefix + "_eskf_trajectory.tum", eskf_poses)))
    return 1;

  graph::GraphMap g = recorder.graph();
  graph::BundleReport rep;
  const Status st = graph::refineBatch(gs, &g, &rep);
  if (st != Status::kOk || !rep.usable) {
    std::cerr << "refinement failed: " << toString(st) << (rep.usable ? "" : " (no usable solution)") << "\n";
    return 1;
  }
  if (!report(graph::writeGraphFiles(g, prefix + "_map.ply", prefix + "_trajectory.tum"))) return 1;
  std::vector<LandmarkInfo> refined_pool = pool;
  for (LandmarkInfo& l : refined_pool) {
    const graph::GraphLandmark& r = g.landmarks.at(l.id);
    l.position = r.position;
    l.covariance = r.covariance;
  }
  if (!report(writePly(prefix + "_map_pool.ply", toPoints(refined_pool)))) return 1;

  if (!stream.truth.empty()) {
    std::vector<StampedPose> truth;
    for (const tools::TruePose& t : stream.truth) truth.push_back(StampedPose{t.t, t.p, t.q});
    if (!report(writeTum(prefix + "_truth.tum", truth))) return 1;
  }
  if (!stream.scene_json.empty() || stream.has_globe) {
    std::ofstream scene(prefix + "_scene.yaml");
    if (!stream.scene_json.empty())
      scene << stream.scene_json << "\n";  // JSON is YAML
    else
      scene << "centre: [" << stream.globe_centre.x() << ", " << stream.globe_centre.y() << ", "
            << stream.globe_centre.z() << "]\nradius: " << stream.globe_radius << "\n";
  }
  std::printf("filter: %zu frames recorded, %d rejected, %d with outcomes unlike the report's counts; pool %zu landmarks\n",
              eskf_poses.size(), rejected, recorder.mismatchedFrames(), pool.size());
  std::printf("graph: %zu keyframes, %zu landmarks, %zu observations; cost %.1f -> %.1f in %d iterations\n",
              g.keyframes.size(), g.landmarks.size(), g.observations.size(), rep.initial_cost, rep.final_cost,
              rep.iterations);
  std::printf("wrote %s_{eskf_map.ply,eskf_trajectory.tum,map.ply,map_pool.ply,trajectory.tum}\n", prefix.c_str());
  return 0;
}
