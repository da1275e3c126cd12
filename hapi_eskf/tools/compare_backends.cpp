// compare_backends: one SLAM back end (slam_backend.hpp, any backend_algorithm)
// on a recorded landmark stream (landmark_stream.hpp), scored per time step
// and per landmark with the metrics of Kock 2021's back-end comparison
// (docs/DESIGN.md "Back ends", "Comparison metrics"). A tool, not a test;
// tools/eval/compare_backends.py runs it for every back end and writes the
// table and the plots (docs/BACKENDS.md).
//
//   compare_backends STREAM.txt|--synthetic-orbit[=SEED,...] --algorithm eskf|seif|graph|fastslam2 --out DIR [--label NAME]
//                    [--frames N] [--truth-offset S] [--refine] [key=value ...]
//
// --truth-offset: t_truth = t_frame + S (the simulator's truth is on the IMU
// clock: the bag's /ground_truth/calibration time_offset_s).
//
// The back end starts at the identity at the first frame (its world is the
// first camera); the truth is moved into that world with the true first
// camera pose (anchored, no alignment fit), so errors and NEES are those of
// the estimate and covariance as the back end states them.
// Per step (DIR/NAME_steps.csv): position error |p - p_true| [m], rotation
// error |Log(R^T R_true)| [rad], their NEES (3 dof each, the back end's 6x6
// pose covariance), map MAE and mean map NEES over the current landmarks
// whose truth is known, pool size, and the per-stage times [ms].
// Per landmark at the end (DIR/NAME_landmarks.csv): error, NEES, times
// observed. The truth of a landmark is where the ray of the measurement that
// created it meets the true surface (globe streams; no map metrics without a
// globe). Summary: DIR/NAME_summary.txt (key value lines).
// Loop closure: per step, oldest_seen_step is the step that created the
// oldest landmark this frame observed (-1: none). Going round an orbit it
// trails the current step by about one field of view; when the camera comes
// back to landmarks of the start it drops to near 0. Per landmark:
// first_step and last_seen_step.
//
// --refine (eskf and graph, built with Ceres): after the run, the full batch
// refinement (docs/DESIGN.md "Graph SLAM", batch) of the graph's own
// snapshot, or of the ES-EKF's run recorded as a graph (eskf_recording.hpp),
// scored before and after on the same frames and landmarks: position and
// rotation MAE over every recorded frame, map MAE and NEES over every
// landmark of the graph whose truth is known (summary keys refine_*). These
// are after-the-fact figures (a smoother's), not the per-step ones above.
//
// Background work (graph's window solve) is waited for after every frame
// (SlamBackend::settle()), so the figures are those of a back end whose
// solver keeps up with the frames and do not depend on the machine's speed;
// its time is the t_background_ms column and counts in the frame's total.
#include "hapi_eskf/backend/measurement_model.hpp"
#include "hapi_eskf/slam_backend_factory.hpp"
#include "hapi_eskf/so3.hpp"
#include "landmark_stream.hpp"
#include "stream_source.hpp"

#ifdef HAPI_ESKF_WITH_GRAPH
#include "hapi_eskf/graph/batch_refinement.hpp"
#include "hapi_eskf/graph/eskf_recording.hpp"
#include "hapi_eskf/graph/graph_slam.hpp"
#endif

#include <hapi_nodelet_kit/sample_quantiles.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

using namespace hapi_eskf;

namespace {

struct Anchor {
  Mat3 R = Mat3::Identity();  // true first camera -> truth world
  Vec3 t = Vec3::Zero();
  Vec3 toFilter(const Vec3& x) const { return R.transpose() * (x - t); }
  // Errors of the pose x (filter world) against the true pose g (truth
  // world): position p_true - p [m] and rotation Log(R^T R_true) [rad].
  void poseErrors(const tools::TruePose& g, const PoseState& x, Vec3* ep, Vec3* er) const {
    *ep = toFilter(g.p) - x.p;
    const Mat3 R_true = R.transpose() * g.q.toRotationMatrix();
    *er = logSO3(x.q.toRotationMatrix().transpose() * R_true);
  }
};

// The true camera pose at time t (truth clock), interpolated (position
// linearly, orientation by slerp); held at the ends.
tools::TruePose truthAt(const std::vector<tools::TruePose>& gt, double t) {
  auto it = std::lower_bound(gt.begin(), gt.end(), t, [](const tools::TruePose& g, double s) { return g.t < s; });
  if (it == gt.end()) return gt.back();
  if (it == gt.begin()) return *it;
  const tools::TruePose &a = *(it - 1), &b = *it;
  const double u = b.t > a.t ? (t - a.t) / (b.t - a.t) : 0.0;
  tools::TruePose g;
  g.t = t;
  g.p = (1 - u) * a.p + u * b.p;
  g.q = a.q.slerp(u, b.q);
  return g;
}

// Where the camera ray along z (camera frame) from the true pose meets the
// globe (the near intersection); false when it misses.
bool surfacePoint(const tools::TruePose& g, const Vec3& z, const Vec3& centre, double radius, Vec3* out) {
  const Vec3 d = g.q.toRotationMatrix() * z.normalized();
  const Vec3 o = g.p - centre;
  const double b = d.dot(o), c = o.squaredNorm() - radius * radius, disc = b * b - c;
  if (disc < 0) return false;
  const double s = -b - std::sqrt(disc);
  if (s <= 0) return false;
  *out = g.p + s * d;
  return true;
}

double nees(const Vec3& e, const Mat3& C) {
  const Eigen::LDLT<Mat3> ldlt(C);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) return std::nan("");
  return e.dot(ldlt.solve(e));
}

double mean(const std::vector<double>& v) {
  double s = 0;
  int n = 0;
  for (double x : v)
    if (std::isfinite(x)) { s += x; ++n; }
  return n ? s / n : std::nan("");
}

#ifdef HAPI_ESKF_WITH_GRAPH
// A graph's trajectory (every recorded frame, else the keyframes) and map
// against the truth (landmarks without a known truth are skipped).
struct GraphScore {
  double pos_mae = 0, rot_mae = 0, map_mae = 0, map_nees = 0;
  std::size_t frames = 0, landmarks = 0;
};

GraphScore scoreGraph(const graph::GraphMap& g, const std::vector<tools::TruePose>& truth, const Anchor& anchor,
                      double truth_offset, const std::map<uint64_t, Vec3>& truth_of) {
  std::vector<PoseState> poses;
  std::vector<double> stamps;
  if (g.frames.empty()) {
    for (const graph::Keyframe& k : g.keyframes) {
      PoseState x;
      x.p = k.p;
      x.q = k.q;
      poses.push_back(x);
      stamps.push_back(k.stamp);
    }
  } else {
    for (const graph::FramePose& f : g.frames) {
      poses.push_back(g.framePose(f));
      stamps.push_back(f.stamp);
    }
  }
  std::vector<double> ep, er, em, nm;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    Vec3 e_p, e_r;
    anchor.poseErrors(truthAt(truth, stamps[i] + truth_offset), poses[i], &e_p, &e_r);
    ep.push_back(e_p.norm());
    er.push_back(e_r.norm());
  }
  for (const auto& kv : g.landmarks) {
    const auto it = truth_of.find(kv.first);
    if (it == truth_of.end()) continue;
    const Vec3 e = kv.second.position - it->second;
    em.push_back(e.norm());
    nm.push_back(nees(e, kv.second.covariance));
  }
  GraphScore s;
  s.pos_mae = mean(ep);
  s.rot_mae = mean(er);
  s.map_mae = mean(em);
  s.map_nees = mean(nm);
  s.frames = poses.size();
  s.landmarks = em.size();
  return s;
}
#endif

}  // namespace

int main(int argc, char** argv) {
  const std::string usage = std::string("usage: compare_backends ") + tools::kStreamSourceUsage +
                            " --algorithm eskf|seif|graph|fastslam2 --out DIR [--label NAME] "
                            "[--frames N] [--truth-offset S] [--refine] [key=value ...]\n";
  if (argc < 2 || std::string(argv[1]) == "--help") {
    std::cerr << usage;
    return argc < 2 ? 1 : 0;
  }
  EskfSettings s;
  std::string out_dir, label;
  int max_frames = -1;
  double truth_offset = 0.0;
  bool refine = false;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--refine") { refine = true; continue; }
    if (a == "--out" && i + 1 < argc) { out_dir = argv[++i]; continue; }
    if (a == "--label" && i + 1 < argc) { label = argv[++i]; continue; }
    if (a == "--frames" && i + 1 < argc) { max_frames = std::stoi(argv[++i]); continue; }
    if (a == "--truth-offset" && i + 1 < argc) { truth_offset = std::stod(argv[++i]); continue; }
    if (a == "--algorithm" && i + 1 < argc) {
      const std::string err = setFieldFromText(&s, "backend_algorithm", argv[++i]);
      if (!err.empty()) { std::cerr << err << "\n"; return 1; }
      continue;
    }
    const auto eq = a.find('=');
    const std::string err =
        eq == std::string::npos ? "unknown argument " + a : setFieldFromText(&s, a.substr(0, eq), a.substr(eq + 1));
    if (!err.empty()) { std::cerr << err << "\n" << usage; return 1; }
  }
  if (out_dir.empty()) { std::cerr << usage; return 1; }
  if (label.empty()) label = toString(s.backend_algorithm);
  if (s.motion_model == MotionModelKind::kInertial) {
    std::cerr << "motion_model inertial: its world is gravity-aligned, not the first camera; not supported here\n";
    return 1;
  }
  tools::LandmarkStream stream;
  std::string err;
  if (!tools::loadStreamSource(argv[1], &stream, &err)) {
    std::cerr << err << "\n";
    return 1;
  }
  if (stream.frames.empty() || stream.truth.empty()) { std::cerr << "stream without frames or truth\n"; return 1; }
  std::vector<ImuSample> imu;
  for (const ImuSample& m : stream.imu) imu.push_back(imuSampleOnCameraClock(m.stamp, m.gyro, m.accel, s));
  auto backend = makeSlamBackend(s, stream.frames[0].descriptor_length, stream.extrinsic.value_or(CameraExtrinsic()),
                                 &err);
  if (!backend) { std::cerr << err << "\n"; return 1; }
  if (s.motion_model != MotionModelKind::kConstantVelocity && (imu.empty() || !backend->supportsImu())) {
    std::cerr << "motion_model " << toString(s.motion_model) << " needs IMU samples and a back end that uses them\n";
    return 1;
  }
  const double t0 = stream.frames[0].stamp;
  if (backend->reset(PoseState(), t0) != Status::kOk) { std::cerr << "reset failed\n"; return 1; }
#ifdef HAPI_ESKF_WITH_GRAPH
  // --refine: the ES-EKF's run is recorded as a graph; Graph SLAM has its own.
  Eskf* const eskf = refine ? graph::recordableEskf(backend.get(), s.backend_algorithm) : nullptr;
  std::unique_ptr<graph::EskfRecorder> recorder;
  if (eskf) recorder = std::make_unique<graph::EskfRecorder>(s.graph.keyframe_min_observations);
  const graph::GraphSlam* graph_slam = refine ? graph::graphSlamOf(backend.get()) : nullptr;
  if (refine && !eskf && !graph_slam) {
    std::cerr << "--refine: only eskf and graph have a graph to refine\n";
    return 1;
  }
#else
  if (refine) {
    std::cerr << "--refine: Graph SLAM is not built here (needs Ceres, libceres-dev)\n";
    return 1;
  }
#endif
  Anchor anchor;
  {
    const tools::TruePose g0 = truthAt(stream.truth, t0 + truth_offset);
    anchor.R = g0.q.toRotationMatrix();
    anchor.t = g0.p;
  }
  const std::string prefix = out_dir + "/" + label;
  std::FILE* steps = std::fopen((prefix + "_steps.csv").c_str(), "w");
  if (!steps) { std::cerr << "cannot write " << prefix << "_steps.csv\n"; return 1; }
  std::fprintf(steps,
               "step,t,pos_err,rot_err,nees_pos,nees_rot,map_mae,map_nees,map_n,landmarks,status,t_total_ms,"
               "t_predict_ms,t_association_ms,t_update_ms,t_removal_ms,t_addition_ms,t_background_ms,oldest_seen_step\n");
  std::map<uint64_t, Vec3> truth_of;  // landmark id -> true point (filter world)
  std::map<uint64_t, int> first_step, last_step;  // landmark id -> step that created / last observed it
  std::vector<double> pos_err, rot_err, nees_pos, nees_rot, map_mae, map_nees, total_ms;
  const auto processFrame = [&](const StereoFrame& f, IterationReport* rep) {
#ifdef HAPI_ESKF_WITH_GRAPH
    if (recorder) return recorder->processFrame(eskf, f, rep);
#endif
    return backend->processFrame(f, rep);
  };
  std::size_t next_imu = 0;
  int n_errors = 0;
  const int n_frames = max_frames > 0 ? std::min<int>(max_frames, stream.frames.size()) : stream.frames.size();
  for (int k = 0; k < n_frames; ++k) {
    const StereoFrame& f = stream.frames[k];
    if (backend->supportsImu())
      for (; next_imu < imu.size() && imu[next_imu].stamp <= f.stamp; ++next_imu)
        if (imu[next_imu].stamp > backend->time()) backend->addImu(imu[next_imu]);
    IterationReport rep;
    Status st = f.measurements.empty() ? backend->predictTo(f.stamp) : processFrame(f, &rep);
    if (st != Status::kOk) ++n_errors;
    const auto settle_start = std::chrono::steady_clock::now();
    backend->settle();
    const double background_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - settle_start).count();
    const tools::TruePose g = truthAt(stream.truth, f.stamp + truth_offset);
    const PoseState x = backend->pose();
    const Mat6 C = backend->cameraPoseCovariance();
    Vec3 ep, er;
    anchor.poseErrors(g, x, &ep, &er);
    pos_err.push_back(ep.norm());
    rot_err.push_back(er.norm());
    nees_pos.push_back(nees(ep, C.topLeftCorner<3, 3>()));
    nees_rot.push_back(nees(er, C.bottomRightCorner<3, 3>()));
    total_ms.push_back(rep.t_total_ms + background_ms);
    // Map: new landmarks get their truth from the ray that created them.
    const std::vector<LandmarkInfo> map = backend->landmarks();
    std::vector<double> e_map, n_map;
    int oldest_seen = -1;
    for (const LandmarkInfo& l : map) {
      first_step.emplace(l.id, k);
      if (l.last_seen == f.stamp) {
        last_step[l.id] = k;
        if (l.times_observed > 1 && (oldest_seen < 0 || first_step[l.id] < oldest_seen)) oldest_seen = first_step[l.id];
      }
      if (stream.has_globe && !truth_of.count(l.id) && l.times_observed == 1 && l.last_seen == f.stamp) {
        const Vec3 z = x.q.toRotationMatrix().transpose() * (l.position - x.p);
        Vec3 X;
        if (surfacePoint(g, z, stream.globe_centre, stream.globe_radius, &X)) truth_of[l.id] = anchor.toFilter(X);
      }
      const auto it = truth_of.find(l.id);
      if (it == truth_of.end()) continue;
      const Vec3 e = l.position - it->second;
      e_map.push_back(e.norm());
      n_map.push_back(nees(e, l.covariance));
    }
    map_mae.push_back(mean(e_map));
    map_nees.push_back(mean(n_map));
    std::fprintf(steps, "%d,%.6f,%.9g,%.9g,%.6g,%.6g,%.9g,%.6g,%zu,%d,%s,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%d\n", k,
                 f.stamp - t0, pos_err.back(), rot_err.back(), nees_pos.back(), nees_rot.back(), map_mae.back(),
                 map_nees.back(), e_map.size(), backend->numLandmarks(), toString(st), total_ms.back(),
                 rep.t_predict_ms, rep.t_association_ms, rep.t_update_ms, rep.t_removal_ms, rep.t_addition_ms,
                 background_ms, oldest_seen);
  }
  std::fclose(steps);
  // Per landmark, final map.
  std::FILE* lm = std::fopen((prefix + "_landmarks.csv").c_str(), "w");
  std::fprintf(lm, "id,err,nees,times_observed,sigma_max,first_step,last_seen_step\n");
  std::vector<double> final_err, final_nees;
  for (const LandmarkInfo& l : backend->landmarks()) {
    const auto it = truth_of.find(l.id);
    if (it == truth_of.end()) continue;
    const Vec3 e = l.position - it->second;
    final_err.push_back(e.norm());
    final_nees.push_back(nees(e, l.covariance));
    const Eigen::SelfAdjointEigenSolver<Mat3> es(l.covariance);
    const auto last = last_step.find(l.id);
    std::fprintf(lm, "%llu,%.9g,%.6g,%d,%.6g,%d,%d\n", static_cast<unsigned long long>(l.id), final_err.back(),
                 final_nees.back(), l.times_observed, std::sqrt(std::max(0.0, es.eigenvalues().maxCoeff())),
                 first_step[l.id], last == last_step.end() ? -1 : last->second);
  }
  std::fclose(lm);
  std::FILE* sum = std::fopen((prefix + "_summary.txt").c_str(), "w");
  std::fprintf(sum, "algorithm %s\nstorage %s\nframes %d\nerrors %d\n", backend->name(), backend->storage().c_str(),
               n_frames, n_errors);
  std::fprintf(sum, "mae_pos_m %.9g\nmae_rot_rad %.9g\nmae_map_m %.9g\n", mean(pos_err), mean(rot_err), mean(map_mae));
  std::fprintf(sum, "mean_nees_pos %.6g\nmean_nees_rot %.6g\nmean_nees_map %.6g\n", mean(nees_pos), mean(nees_rot),
               mean(map_nees));
  std::fprintf(sum, "final_map_mae_m %.9g\nfinal_map_nees %.6g\nfinal_map_n %zu\n", mean(final_err), mean(final_nees),
               final_err.size());
#ifdef HAPI_ESKF_WITH_GRAPH
  if (refine) {
    graph::GraphMap g = recorder ? recorder->graph() : graph_slam->snapshot();
    const GraphScore before = scoreGraph(g, stream.truth, anchor, truth_offset, truth_of);
    graph::BundleReport rep;
    const auto start = std::chrono::steady_clock::now();
    const Status st = graph::refineBatch(graph::graphSettings(s), &g, &rep);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (st != Status::kOk || !rep.usable) {
      std::cerr << "refinement failed: " << toString(st) << "\n";
      return 1;
    }
    const GraphScore after = scoreGraph(g, stream.truth, anchor, truth_offset, truth_of);
    std::fprintf(sum, "refine_frames %zu\nrefine_landmarks %zu\nrefine_keyframes %zu\nrefine_iterations %d\n",
                 after.frames, after.landmarks, g.keyframes.size(), rep.iterations);
    std::fprintf(sum, "refine_s %.3f\nrefine_cost_before %.6g\nrefine_cost_after %.6g\n", seconds, rep.initial_cost,
                 rep.final_cost);
    for (const auto& kv : {std::make_pair("before", before), std::make_pair("after", after)})
      std::fprintf(sum, "refine_%s_pos_m %.9g\nrefine_%s_rot_rad %.9g\nrefine_%s_map_m %.9g\nrefine_%s_map_nees %.6g\n",
                   kv.first, kv.second.pos_mae, kv.first, kv.second.rot_mae, kv.first, kv.second.map_mae, kv.first,
                   kv.second.map_nees);
    std::printf("%s batch refinement (%zu frames, %zu landmarks, %.1f s): position %.2f -> %.2f mm, rotation %.4f -> "
                "%.4f rad, map %.2f -> %.2f mm, map NEES %.2f -> %.2f\n",
                label.c_str(), after.frames, after.landmarks, seconds, 1e3 * before.pos_mae, 1e3 * after.pos_mae,
                before.rot_mae, after.rot_mae, 1e3 * before.map_mae, 1e3 * after.map_mae, before.map_nees,
                after.map_nees);
  }
#endif
  const auto ms = [&](double q) { return hapi_nodelet_kit::quantileRoundedPosition(total_ms, q, std::nan("")); };
  std::fprintf(sum, "ms_mean %.4f\nms_p50 %.4f\nms_p99 %.4f\nms_max %.4f\n", mean(total_ms), ms(0.5), ms(0.99),
               ms(1.0));
  std::fclose(sum);
  std::printf("%s: MAE pos %.2f mm rot %.4f rad map %.2f mm | NEES pos %.2f rot %.2f map %.2f | %.1f ms/frame\n",
              label.c_str(), 1e3 * mean(pos_err), mean(rot_err), 1e3 * mean(map_mae), mean(nees_pos), mean(nees_rot),
              mean(map_nees), mean(total_ms));
  return 0;
}
