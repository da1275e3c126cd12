// pipeline_latency: the whole pipeline without ROS on one simulated recording
// (hapi_sim's Scenario, the suite the test bags are written from): the front
// end's StereoPipeline, the StereoFrame the two nodelets exchange
// (stereo_frame_link.hpp) and the ES-EKF, which first takes the IMU samples up
// to the image's stamp, in the order of the back-end nodelet's worker. Each
// frame is timed from its two images in memory to the pose that frame
// corrects: front end, then back end (IMU samples + filter iteration). Not in
// it: exposure, transport and queueing (docs/BENCHMARKS.md "Latency a user
// feels" has the ROS figures with them).
//
// Several variants run over the same rendered images and IMU samples in one
// process, so their times compare as ratios of one run, and each variant's
// trajectory is compared with the first variant's (the GPU kernels return
// the CPU's features, the CUDA backend the CPU backend's numbers).
//
//   pipeline_latency SCENARIO [--variant FRONTEND:BACKEND]... [--frontend name=value]...
//                    [--out PREFIX] [key=value ...]
//
// SCENARIO: the options of make_sim_bag (hapi_sim/scenario_options.hpp),
//   e.g. --scene skin --trajectory handheld --seed 1 --duration 30.
// FRONTEND: cpu | gpu (ORB and matching with the CUDA kernels, use_gpu);
// BACKEND: cpu | cuda (the back end's `backend` setting). Default variants:
//   cpu:cpu, plus gpu:cuda where built with CUDA.
// --frontend name=value: a front-end setting by its ROS name
//   (config/frontend.yaml, e.g. fast_threshold=8), checked against its range.
// key=value: a back-end setting (config/eskf.yaml names, checked likewise).
//   The motion model is `inertial` unless set: the main job's model when the
//   recording has IMU. The filter gets the camera-IMU extrinsic and time
//   offset that the bags tell a filter (/tf_static, /calibration): the true
//   ones except under --realism real.
// --out PREFIX: PREFIX_truth.tum and PREFIX_<frontend>_<backend>.tum (TUM:
//   t x y z qx qy qz qw, the left camera per frame, on the camera clock) for
//   tools/eval/evaluate.py, and PREFIX_<frontend>_<backend>_times.txt (per
//   frame: t, front end ms, back end ms, landmarks in the filter).
// Exit status: 0 when every variant corrected poses, 1 otherwise, 2 on a
// bad command line.
//
// The first frame of each variant is processed once before the timed run
// and discarded: it creates the CUDA context and the GPU buffers.
#include "stereo_frame_link.hpp"

#include <hapi_dataset/command_line.hpp>
#include <hapi_eskf/eskf/storage_factory.hpp>
#include <hapi_eskf/eskf/eskf.hpp>
#include <hapi_eskf/eskf/motion_model.hpp>
#include <hapi_eskf/settings.hpp>
#include <hapi_frontend/param_spec.hpp>
#include <hapi_frontend/stereo_pipeline.hpp>
#include <hapi_nodelet_kit/sample_quantiles.hpp>
#include <hapi_sim/scenario.hpp>
#include <hapi_sim/scenario_options.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
using hapi_eskf::Vec3;

double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// Everything the variants share: rendered once.
struct Recording {
  struct Frame {
    double stamp = 0.0;  // camera clock [s]
    cv::Mat left, right;
    hapi_sim::Pose truth;  // left camera in the scene at the frame's true time
  };
  struct Imu {
    double stamp = 0.0;  // IMU clock [s]
    Vec3 gyro = Vec3::Zero(), accel = Vec3::Zero();
  };
  std::vector<Frame> frames;
  std::vector<Imu> imu;
  hapi_frontend::CameraCalib left, right;
  hapi_eskf::CameraExtrinsic extrinsic;
};

double epochSeconds(int64_t ns) { return static_cast<double>(hapi_sim::kSimEpochNs + ns) * 1e-9; }

Recording record(const hapi_sim::Scenario& sc) {
  Recording rec;
  rec.left = hapi_frontend::copyCameraInfo(sc.rig().leftInfo());
  rec.right = hapi_frontend::copyCameraInfo(sc.rig().rightInfo());
  // X_cam = T_cam_imu X_imu; the filter takes the camera in the IMU frame, as
  // the device believes it (the truth except under --realism real).
  const hapi_sim::Pose& T = sc.believedCalibration().T_cam_imu;
  rec.extrinsic.R_imu_cam = T.q.toRotationMatrix().transpose();
  rec.extrinsic.p_imu_cam = -(rec.extrinsic.R_imu_cam * T.p);
  sc.play(
      [&](int64_t i, const hapi_sim::ImuReading& r) {
        rec.imu.push_back({epochSeconds(sc.imuTimeNs(i)), r.gyro, r.accel});
      },
      [&](int64_t k, const cv::Mat& left, const cv::Mat& right) {
        Recording::Frame f;
        f.stamp = epochSeconds(sc.frameStampNs(k));
        f.left = left.clone();
        f.right = right.clone();
        f.truth = sc.leftCameraInScene(sc.frameTimeNs(k) * 1e-9).pose();
        rec.frames.push_back(std::move(f));
      });
  return rec;
}

struct Variant {
  bool gpu_frontend = false;
  hapi_eskf::BackendKind backend = hapi_eskf::BackendKind::kCpu;
  std::string name() const {
    return std::string(gpu_frontend ? "gpu" : "cpu") + "_" + hapi_eskf::toString(backend);
  }
};

struct Pose {
  double stamp = 0.0;
  Vec3 p = Vec3::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  int pool = 0;  // landmarks in the filter after the frame
};

struct RunResult {
  std::vector<double> frontend_ms, backend_ms, total_ms;  // per frame with a corrected pose
  std::vector<Pose> poses;
  int gpu_frames = 0;     // frames whose features came from the GPU
  int awaiting = 0;       // frames before the inertial alignment (no pose)
  int errors = 0;         // frames the front end or the filter refused
  double landmarks = 0;   // mean landmarks per frame
  std::string failure;    // the variant could not run at all
};

RunResult run(const Variant& v, const Recording& rec, hapi_frontend::PipelineParams fp, hapi_eskf::EskfSettings s) {
  RunResult out;
  fp.use_gpu = v.gpu_frontend;
  s.backend = v.backend;
  std::unique_ptr<hapi_frontend::StereoPipeline> fe;
  try {
    fe = std::make_unique<hapi_frontend::StereoPipeline>(fp);
  } catch (const std::exception& e) {
    out.failure = e.what();
    return out;
  }
  const std::string calib_error = fe->setCalibration(rec.left, rec.right);
  if (!calib_error.empty()) {
    out.failure = "calibration: " + calib_error;
    return out;
  }
  hapi_frontend::StereoFrameResult warm;
  fe->process(rec.frames[0].left, rec.frames[0].right, cv::Mat(), &warm);

  std::unique_ptr<hapi_eskf::Eskf> eskf;
  std::size_t next_imu = 0;
  double landmark_sum = 0;
  for (std::size_t k = 0; k < rec.frames.size(); ++k) {
    const Recording::Frame& f = rec.frames[k];
    const Clock::time_point t0 = Clock::now();
    hapi_frontend::StereoFrameResult res;
    std::string error = fe->process(f.left, f.right, cv::Mat(), &res);
    hapi_eskf::StereoFrame frame;
    if (error.empty()) hapi_latency::toStereoFrame(res, f.stamp, &frame, &error);
    const double fe_ms = msSince(t0);
    if (!error.empty()) {
      ++out.errors;
      continue;
    }
    out.gpu_frames += res.used_gpu;
    landmark_sum += frame.measurements.size();
    const Clock::time_point t1 = Clock::now();
    // The back-end nodelet creates its filter with the first frame that has
    // landmarks (their descriptor length) and resets it at that stamp.
    if (!eskf) {
      if (frame.measurements.empty()) continue;
      auto backend = hapi_eskf::makeBackend(s, frame.descriptor_length, &out.failure);
      if (!backend) return out;
      eskf = std::make_unique<hapi_eskf::Eskf>(s, std::move(backend), rec.extrinsic);
      eskf->reset(hapi_eskf::PoseState(), f.stamp);
    }
    // Its worker then applies the IMU samples up to the image (applyImu).
    for (; next_imu < rec.imu.size(); ++next_imu) {
      const hapi_eskf::ImuSample m =
          hapi_eskf::imuSampleOnCameraClock(rec.imu[next_imu].stamp, rec.imu[next_imu].gyro, rec.imu[next_imu].accel, s);
      if (m.stamp > f.stamp) break;
      if (m.stamp > eskf->time()) eskf->addImu(m);
    }
    hapi_eskf::IterationReport rep;
    const hapi_eskf::Status st = eskf->processFrame(frame, &rep);
    const double be_ms = msSince(t1);
    if (st == hapi_eskf::Status::kAwaitingImu) {
      ++out.awaiting;
      continue;
    }
    if (st != hapi_eskf::Status::kOk) {
      ++out.errors;
      continue;
    }
    out.frontend_ms.push_back(fe_ms);
    out.backend_ms.push_back(be_ms);
    out.total_ms.push_back(fe_ms + be_ms);
    const hapi_eskf::PoseState x = eskf->pose();
    out.poses.push_back({f.stamp, x.p, x.q, eskf->numLandmarks()});
  }
  out.landmarks = landmark_sum / std::max<std::size_t>(1, rec.frames.size());
  return out;
}

double percentile(const std::vector<double>& v, double q) {
  return hapi_nodelet_kit::quantileNearestRank(v, q, 0.0);
}

std::string spread(const std::vector<double>& v) { return hapi_nodelet_kit::formatP50P99Max(v, 2); }

// Largest distance between two runs' positions at the frames both have.
double maxPositionDifference(const std::vector<Pose>& a, const std::vector<Pose>& b, int* compared) {
  double worst = 0.0;
  *compared = 0;
  std::size_t j = 0;
  for (const Pose& pa : a) {
    while (j < b.size() && b[j].stamp < pa.stamp) ++j;
    if (j == b.size() || b[j].stamp != pa.stamp) continue;
    worst = std::max(worst, (pa.p - b[j].p).norm());
    ++*compared;
  }
  return worst;
}

void writeTimes(const std::string& path, const RunResult& r) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error("cannot write " + path);
  for (std::size_t i = 0; i < r.poses.size(); ++i)
    std::fprintf(f, "%.9f %.3f %.3f %d\n", r.poses[i].stamp, r.frontend_ms[i], r.backend_ms[i], r.poses[i].pool);
  std::fclose(f);
}

void writeTum(const std::string& path, const std::vector<Pose>& poses) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error("cannot write " + path);
  for (const Pose& p : poses)
    std::fprintf(f, "%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", p.stamp, p.p.x(), p.p.y(), p.p.z(), p.q.x(), p.q.y(),
                 p.q.z(), p.q.w());
  std::fclose(f);
}

[[noreturn]] void usage(const std::string& why) {
  std::cerr << "pipeline_latency: " << why << "\n"
            << "usage: pipeline_latency " << hapi_sim::kScenarioOptionsUsage << "\n"
            << "  [--variant cpu|gpu:cpu|cuda]... [--frontend name=value]... [--out PREFIX] [key=value ...]\n";
  std::exit(2);
}

bool parseVariant(const std::string& text, Variant* v) {
  const auto colon = text.find(':');
  if (colon == std::string::npos) return false;
  const std::string fe = text.substr(0, colon);
  if (fe != "cpu" && fe != "gpu") return false;
  v->gpu_frontend = fe == "gpu";
  return hapi_eskf::parseBackendKind(text.substr(colon + 1), &v->backend);
}

}  // namespace

int main(int argc, char** argv) {
  hapi_sim::ScenarioConfig cfg;
  hapi_frontend::PipelineParams fp;
  hapi_eskf::EskfSettings s;
  hapi_eskf::setFieldFromText(&s, "motion_model", "inertial");
  std::vector<Variant> variants;
  std::string out_prefix;
  std::vector<std::pair<std::string, std::string>> eskf_overrides;
  // --key value pairs, and key=value arguments of their own for the back end.
  std::vector<char*> options{argv[0]};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto eq = a.find('=');
    if (a.rfind("--", 0) == 0) {
      options.push_back(argv[i]);
      if (i + 1 < argc) options.push_back(argv[++i]);
    } else if (eq != std::string::npos) {
      eskf_overrides.emplace_back(a.substr(0, eq), a.substr(eq + 1));
    } else {
      usage("unexpected argument " + a);
    }
  }
  hapi_dataset::forEachOption(static_cast<int>(options.size()), options.data(), usage,
                              [&](const std::string& k, const std::string& v) {
                                if (hapi_sim::setScenarioOption(k, v, &cfg)) return;
                                if (k == "--variant") {
                                  Variant var;
                                  if (!parseVariant(v, &var)) usage("--variant must be cpu|gpu:cpu|cuda, got " + v);
                                  variants.push_back(var);
                                } else if (k == "--frontend") {
                                  const auto eq = v.find('=');
                                  const std::string err =
                                      eq == std::string::npos
                                          ? "--frontend takes name=value"
                                          : hapi_frontend::setFromText(&fp, v.substr(0, eq), v.substr(eq + 1));
                                  if (!err.empty()) usage(err);
                                } else if (k == "--out") {
                                  out_prefix = v;
                                } else {
                                  usage("unknown option " + k);
                                }
                              });
  if (!cfg.validate().empty()) usage(cfg.validate());
  if (!fp.validate().empty()) usage(fp.validate());
  const hapi_sim::Scenario sc(cfg);
  s.imu_time_offset = sc.believedCalibration().time_offset_ns * 1e-9;
  for (const auto& [key, value] : eskf_overrides) {
    const std::string err = hapi_eskf::setFieldFromText(&s, key, value);
    if (!err.empty()) usage(err);
  }
  if (!s.validate().empty()) usage(s.validate());
  if (variants.empty()) {
    variants.push_back(Variant());
#ifdef HAPI_LATENCY_WITH_CUDA
    variants.push_back(Variant{true, hapi_eskf::BackendKind::kCuda});
#endif
  }

  const Clock::time_point t_render = Clock::now();
  const Recording rec = record(sc);
  std::fprintf(stderr, "[pipeline_latency] scene %s, trajectory %s, seed %u: %zu frames, %zu IMU samples (%.1f s)\n",
               sc.scene().name().c_str(), hapi_sim::trajectoryName(cfg.trajectory).c_str(), cfg.seed,
               rec.frames.size(), rec.imu.size(), msSince(t_render) / 1000.0);
  if (rec.frames.size() < 2) usage("the scenario has fewer than 2 frames");
  if (!out_prefix.empty()) {
    std::vector<Pose> truth;
    for (const Recording::Frame& f : rec.frames) truth.push_back({f.stamp, f.truth.p, f.truth.q});
    writeTum(out_prefix + "_truth.tum", truth);
  }

  std::printf("motion_model %s, %d landmarks per frame at most, pool %d\n\n",
              hapi_eskf::toString(s.motion_model), fp.landmarks_per_frame, s.max_landmarks);
  std::printf("| variant | frames | GPU features | landmarks/frame | front end p50 / p99 / max ms | "
              "back end p50 / p99 / max ms | total p50 / p99 / max ms | total p50 / first | "
              "max distance to first (m) |\n|---|---|---|---|---|---|---|---|---|\n");
  std::vector<RunResult> results;
  int status = 0;
  for (const Variant& v : variants) {
    results.push_back(run(v, rec, fp, s));
    const RunResult& r = results.back();
    if (!r.failure.empty() || r.total_ms.empty()) {
      std::printf("| %s | failed: %s |\n", v.name().c_str(),
                  r.failure.empty() ? "no frame gave a corrected pose" : r.failure.c_str());
      status = 1;
      continue;
    }
    if (!out_prefix.empty()) {
      writeTum(out_prefix + "_" + v.name() + ".tum", r.poses);
      writeTimes(out_prefix + "_" + v.name() + "_times.txt", r);
    }
    int compared = 0;
    const double diff = maxPositionDifference(r.poses, results.front().poses, &compared);
    const double ratio = percentile(r.total_ms, 0.5) / std::max(1e-9, percentile(results.front().total_ms, 0.5));
    std::printf("| %s | %zu (+%d awaiting, %d refused) | %d | %.0f | %s | %s | %s | %.3f | %.3g (%d frames) |\n",
                v.name().c_str(), r.total_ms.size(), r.awaiting, r.errors, r.gpu_frames, r.landmarks,
                spread(r.frontend_ms).c_str(), spread(r.backend_ms).c_str(), spread(r.total_ms).c_str(), ratio, diff,
                compared);
    std::fflush(stdout);
  }
  return status;
}
