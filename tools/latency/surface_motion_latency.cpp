// surface_motion_latency: the surface-motion path without ROS, timed per
// imaging frame from its image in host memory to the SurfaceMotion output
// that carries its flow (docs/BENCHMARKS.md "Surface motion, image to
// output"): ImageFlowTracker (CPU, or CUDA with use_gpu) on the imaging
// camera's frame, then SurfaceMotionEstimator::addFlow and
// outputWithNewFlows, the order of the flow and surface-motion nodelets.
// Not in it: exposure, readout, transport and queueing (the live figures
// with them are in docs/MOTION.md "Live").
//
// The estimator's other inputs come from the simulator's truth: the imaging
// camera's odometry at the IMU rate (pose, twist) and a map snapshot at
// every stereo frame, the true surface under a grid of pixels about the
// measurement pixel. Their source does not change the work per flow; the
// system's accuracy is measured by tools/eval/motion_study.py. The odometry
// up to the first sample at or after a frame's stamp is given before its
// flow, as when the odometry is on time. The variants run over the same rendered frames in one
// process, so their times compare as ratios of one run.
//
//   surface_motion_latency SCENARIO [--variant cpu|gpu]... [--tracker name=value]...
//                          [--estimator key=value]...
//
// SCENARIO: the options of make_sim_bag (hapi_sim/scenario_options.hpp) with
//   an imaging camera, e.g. --scene skin --trajectory measurement --seed 1
//   --duration 7 --imaging-rate 40.
// --variant: the tracker's backend (default cpu, plus gpu); a gpu variant
//   whose tracker falls back to the CPU is reported as such and fails.
// --tracker name=value: an ImageFlowParams setting (config/image_flow.yaml).
// --estimator key=value: a SurfaceMotionSettings setting.
// Exit status: 0 when every variant fused flows, 1 otherwise, 2 on a bad
// command line.
#include <hapi_dataset/command_line.hpp>
#include <hapi_eskf/settings_table.hpp>
#include <hapi_eskf/surface_motion/surface_motion_estimator.hpp>
#include <hapi_frontend/image_flow_params.hpp>
#include <hapi_frontend/image_flow_tracker.hpp>
#include <hapi_nodelet_kit/sample_quantiles.hpp>
#include <hapi_sim/scenario.hpp>
#include <hapi_sim/scenario_options.hpp>
#include <hapi_sim/surface_motion_truth.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
namespace sm = hapi_eskf::surface_motion;

double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// Everything the variants share: rendered once.
struct Recording {
  struct Imaging {
    std::int64_t stamp_ns = 0;  // camera clock, mid-exposure
    cv::Mat image;
  };
  struct MapSnapshot {
    double t = 0;
    std::vector<hapi_eskf::Vec3> points;
  };
  std::vector<Imaging> frames;
  std::vector<sm::CameraOdometry> odometry;  // the imaging camera's, camera clock
  std::vector<MapSnapshot> maps;
  sm::ImagingCamera camera;
};

double seconds(std::int64_t ns) { return static_cast<double>(ns) * 1e-9; }

// The imaging camera (the left camera) in the scene at true time t, as the
// estimator takes it: pose in the world (the scene), twist in its own frame.
sm::CameraOdometry odometryAt(const hapi_sim::Scenario& sc, double t_true, double stamp) {
  const hapi_sim::MotionSample m = sc.leftCameraInScene(t_true);
  sm::CameraOdometry o;
  o.t = stamp;
  o.T_world_cam.linear() = m.q.toRotationMatrix();
  o.T_world_cam.translation() = m.p;
  o.v = m.q.conjugate() * m.v;
  o.w = m.omega;
  o.twist_covariance = hapi_eskf::Mat6::Identity() * 1e-6;
  return o;
}

// The true surface under a 15 x 15 grid of the imaging camera's pixels,
// 12 px apart about the measurement pixel (the estimator fits its depth to
// the map within 40-80 px of it), in the world (the scene).
std::vector<hapi_eskf::Vec3> surfaceAroundPixel(const hapi_sim::Scenario& sc, double t_true) {
  const hapi_sim::MotionSample m = sc.leftCameraInScene(t_true);
  const Eigen::Vector2d centre = sc.imagingPixel();
  std::vector<hapi_eskf::Vec3> points;
  for (int i = -7; i <= 7; ++i)
    for (int j = -7; j <= 7; ++j) {
      const Eigen::Vector2d px = centre + 12.0 * Eigen::Vector2d(i, j);
      const hapi_sim::SurfaceMotionTruth s = hapi_sim::surfaceMotionTruth(sc.scene(), sc.imagingCamera(), px, 1.0, m);
      if (s.hit) points.push_back(m.q * s.point + m.p);
    }
  return points;
}

Recording record(const hapi_sim::Scenario& sc) {
  Recording rec;
  const hapi_sim::CameraInfoData info = sc.imagingInfo();
  rec.camera.fx = info.K[0];
  rec.camera.fy = info.K[4];
  rec.camera.cx = info.K[2];
  rec.camera.cy = info.K[5];
  for (std::size_t i = 0; i < rec.camera.distortion.size() && i < info.D.size(); ++i)
    rec.camera.distortion[i] = info.D[i];
  rec.camera.width = static_cast<int>(info.width);
  rec.camera.height = static_cast<int>(info.height);
  rec.camera.frame_rate = sc.config().imaging_rate;
  // The camera clock is the IMU clock shifted by the scenario's offsets.
  const double clock_shift = seconds(sc.imagingStampNs(0) - sc.imagingTimeNs(0));
  sc.play(
      [&](std::int64_t i, const hapi_sim::ImuReading&) {
        const double t = seconds(sc.imuTimeNs(i));
        rec.odometry.push_back(odometryAt(sc, t, t + clock_shift));
      },
      [&](std::int64_t k, const cv::Mat&, const cv::Mat&) {
        const double t = seconds(sc.frameTimeNs(k));
        rec.maps.push_back({t + clock_shift, surfaceAroundPixel(sc, t)});
      },
      [&](std::int64_t j, const cv::Mat& image) { rec.frames.push_back({sc.imagingStampNs(j), image.clone()}); });
  return rec;
}

sm::FlowMeasurement toFlowMeasurement(const hapi_frontend::ImageFlowResult& r) {
  sm::FlowMeasurement f;
  f.t_prev = seconds(r.previous_stamp_ns);
  f.t = seconds(r.stamp_ns);
  f.u = r.u;
  f.v = r.v;
  for (int i = 0; i < 6; ++i) f.affine[i] = r.affine[i];
  for (int i = 0; i < 36; ++i) f.covariance[i] = r.covariance(i / 6, i % 6);
  f.inliers = r.inliers;
  f.tracked = r.tracked;
  f.status = static_cast<std::uint8_t>(r.status);
  return f;
}

struct RunResult {
  std::vector<double> track_ms, fuse_ms, total_ms;  // per flow that reached an output
  int flows = 0, fused = 0;
  std::map<std::string, int> outcomes;  // of the flows not fused into an OK output, by reason
  std::string backend, failure;
};

RunResult run(bool gpu, const Recording& rec, hapi_frontend::ImageFlowParams tp, const sm::SurfaceMotionSettings& es) {
  RunResult r;
  tp.use_gpu = gpu;
  hapi_frontend::ImageFlowTracker tracker(tp);
  sm::SurfaceMotionEstimator estimator(es);
  const std::string bad_camera = estimator.setCamera(rec.camera);
  if (!bad_camera.empty()) {
    r.failure = "imaging camera: " + bad_camera;
    return r;
  }
  std::size_t next_odom = 0, next_map = 0;
  for (std::size_t j = 0; j < rec.frames.size(); ++j) {
    const Recording::Imaging& fr = rec.frames[j];
    const double t = seconds(fr.stamp_ns);
    for (; next_map < rec.maps.size() && rec.maps[next_map].t <= t; ++next_map)
      estimator.setMap(rec.maps[next_map].points);
    for (bool covered = false; next_odom < rec.odometry.size() && !covered; ++next_odom) {
      estimator.addOdometry(rec.odometry[next_odom]);
      covered = rec.odometry[next_odom].t >= t;
    }
    const Clock::time_point t0 = Clock::now();
    hapi_frontend::ImageFlowResult flow;
    const hapi_frontend::InputError err = tracker.process(fr.image, fr.stamp_ns, &flow);
    const double track_ms = msSince(t0);
    if (err || flow.status != hapi_frontend::FlowStatus::kOk) continue;
    ++r.flows;
    const Clock::time_point t1 = Clock::now();
    std::string why;
    const sm::FlowOutcome outcome = estimator.addFlow(toFlowMeasurement(flow), &why);
    const std::optional<sm::SurfaceMotionOutput> out = estimator.outputWithNewFlows();
    const double fuse_ms = msSince(t1);
    // The first frame of a variant creates the CUDA context and buffers.
    if (j < 2) continue;
    if (outcome != sm::FlowOutcome::kFused || !out || out->status != sm::MotionStatus::kOk) {
      ++r.outcomes[outcome != sm::FlowOutcome::kFused ? std::string(sm::toString(outcome)) + (why.empty() ? "" : ": " + why)
                                                       : out ? "output: " + out->message : "no output"];
      continue;
    }
    ++r.fused;
    r.track_ms.push_back(track_ms);
    r.fuse_ms.push_back(fuse_ms);
    r.total_ms.push_back(track_ms + fuse_ms);
  }
  r.backend = tracker.backendStatus();
  if (gpu && !tracker.usingGpu()) r.failure = "the tracker runs on the CPU: " + tracker.backendStatus();
  return r;
}

std::string spread(const std::vector<double>& v) { return hapi_nodelet_kit::formatP50P99Max(v, 3); }

[[noreturn]] void usage(const std::string& why) {
  std::cerr << "surface_motion_latency: " << why << "\n"
            << "usage: surface_motion_latency " << hapi_sim::kScenarioOptionsUsage << "\n"
            << "  [--variant cpu|gpu]... [--tracker name=value]... [--estimator key=value]...\n";
  std::exit(2);
}

std::pair<std::string, std::string> keyValue(const std::string& option, const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos) usage(option + " takes name=value, got " + text);
  return {text.substr(0, eq), text.substr(eq + 1)};
}

}  // namespace

int main(int argc, char** argv) {
  hapi_sim::ScenarioConfig cfg;
  hapi_frontend::ImageFlowParams tp;
  sm::SurfaceMotionSettings es;
  std::vector<bool> variants;  // gpu?
  hapi_dataset::forEachOption(argc, argv, usage, [&](const std::string& k, const std::string& v) {
    if (hapi_sim::setScenarioOption(k, v, &cfg)) return;
    if (k == "--variant") {
      if (v != "cpu" && v != "gpu") usage("--variant must be cpu or gpu, got " + v);
      variants.push_back(v == "gpu");
    } else if (k == "--tracker") {
      const auto [name, value] = keyValue(k, v);
      const std::string err = hapi_frontend::setFromText(&tp, name, value);
      if (!err.empty()) usage(err);
    } else if (k == "--estimator") {
      const auto [name, value] = keyValue(k, v);
      const std::string err = hapi_eskf::setTableFieldFromText(&es, name, value);
      if (!err.empty()) usage(err);
    } else {
      usage("unknown option " + k);
    }
  });
  if (!cfg.validate().empty()) usage(cfg.validate());
  if (!(cfg.imaging_rate > 0)) usage("the scenario needs an imaging camera (--imaging-rate)");
  if (!tp.validate().empty()) usage(tp.validate());
  if (!es.validate().empty()) usage(es.validate());
  if (variants.empty()) variants = {false, true};

  const hapi_sim::Scenario sc(cfg);
  const Clock::time_point t_render = Clock::now();
  const Recording rec = record(sc);
  std::fprintf(stderr, "[surface_motion_latency] scene %s, trajectory %s, seed %u: %zu imaging frames at %g Hz (%.1f s)\n",
               sc.scene().name().c_str(), hapi_sim::trajectoryName(cfg.trajectory).c_str(), cfg.seed,
               rec.frames.size(), cfg.imaging_rate, msSince(t_render) / 1000.0);
  if (rec.frames.size() < 4) usage("the scenario has fewer than 4 imaging frames");

  std::printf("| tracker | flows fused / tracked | track p50 / p99 / max ms | fuse and output p50 / p99 / max ms | "
              "image to output p50 / p99 / max ms | p50 / first |\n|---|---|---|---|---|---|\n");
  int status = 0;
  double first_p50 = 0;
  for (bool gpu : variants) {
    const RunResult r = run(gpu, rec, tp, es);
    const char* name = gpu ? "gpu" : "cpu";
    std::string lost;
    for (const auto& [reason, n] : r.outcomes) lost += (lost.empty() ? "" : "; ") + reason + " x" + std::to_string(n);
    if (!r.failure.empty() || r.total_ms.empty()) {
      std::printf("| %s | failed: %s (%s) |\n", name, r.failure.empty() ? "no flow reached an output" : r.failure.c_str(),
                  lost.c_str());
      status = 1;
      continue;
    }
    const double p50 = hapi_nodelet_kit::quantileNearestRank(r.total_ms, 0.5, 0.0);
    if (first_p50 == 0) first_p50 = p50;
    std::printf("| %s (%s) | %d / %d | %s | %s | %s | %.3f |\n", name, r.backend.c_str(), r.fused, r.flows,
                spread(r.track_ms).c_str(), spread(r.fuse_ms).c_str(), spread(r.total_ms).c_str(), p50 / first_p50);
    std::fflush(stdout);
  }
  return status;
}
