// hapi_eskf_imu_bench: the cost of the IMU prediction with a full pool, per
// motion model and backend (docs/BENCHMARKS.md). A filter with K landmarks
// (random, well-posed blocks) takes `samples` IMU samples at `rate` Hz with
// one frame every rate/frame_rate samples; a frame's prediction (the chained
// steps into C, Eskf::predictTo) is timed separately from the per-sample
// steps (Eskf::addImu). Reported: mean per-sample step, mean per-frame flush,
// and their sum per sample (what one IMU sample costs the filter).
//
//   hapi_eskf_imu_bench [--k 2000] [--samples 4000] [--rate 200] [--frame-rate 10] [key=value ...]
#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "hapi_eskf/eskf/eskf.hpp"
#include "hapi_eskf/eskf/storage_factory.hpp"
#include "hapi_eskf/random_draw.hpp"
#include "hapi_eskf/so3.hpp"

#include <chrono>
#include <cstdio>
#include <iostream>
#include <random>
#include <string>
#include <vector>

using namespace hapi_eskf;
using Clock = std::chrono::steady_clock;

int main(int argc, char** argv) {
  int K = 2000, samples = 4000;
  double rate = 200.0, frame_rate = 10.0;
  EskfSettings s;
  s.motion_model = MotionModelKind::kInertial;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--k" && i + 1 < argc) K = std::stoi(argv[++i]);
    else if (a == "--samples" && i + 1 < argc) samples = std::stoi(argv[++i]);
    else if (a == "--rate" && i + 1 < argc) rate = std::stod(argv[++i]);
    else if (a == "--frame-rate" && i + 1 < argc) frame_rate = std::stod(argv[++i]);
    else if (a.find('=') != std::string::npos) {
      const std::string err = setFieldFromText(&s, a.substr(0, a.find('=')), a.substr(a.find('=') + 1));
      if (!err.empty()) { std::cerr << err << "\n"; return 1; }
    } else {
      std::cerr << "usage: hapi_eskf_imu_bench [--k N] [--samples N] [--rate HZ] [--frame-rate HZ] [key=value ...]\n";
      return 1;
    }
  }
  s.max_landmarks = K;
  if (!s.validate().empty()) { std::cerr << s.validate() << "\n"; return 1; }
  if (s.motion_model == MotionModelKind::kConstantVelocity) {
    std::cerr << "motion_model constant_velocity takes no IMU samples\n";
    return 1;
  }
  std::string err;
  auto backend = makeBackend(s, 32, &err);
  if (!backend) { std::cerr << err << "\n"; return 1; }
  Eskf f(s, std::move(backend));
  f.reset(PoseState(), 0.0);
  std::mt19937 rng(1);
  std::normal_distribution<double> g(0.0, 1.0);
  auto sample = [&](double t) {
    return ImuSample{t, Vec3(0.3 * g(rng), 0.3 * g(rng), 0.3 * g(rng)), Vec3(0.5 * g(rng), 0.5 * g(rng), 9.81)};
  };
  const double dt = 1.0 / rate;
  double t = 0.0;
  while (f.awaitingAlignment() || f.time() == 0.0) {
    t += dt;
    f.addImu(sample(t));
  }
  // A full pool: K landmarks with random cross-covariances.
  std::vector<uint8_t> desc(32, 0);
  std::vector<NewLandmarkBlock> blocks(K);
  for (NewLandmarkBlock& b : blocks) {
    const Mat3 R = expSO3(drawVec3(g, rng));
    b.G_pose << Mat3::Identity(), -R * skew(Vec3(g(rng), g(rng), 1.0 + std::abs(g(rng))));
    b.G_z = R;
    b.Cz = 1e-4 * Mat3::Identity();
    b.descriptor = desc.data();
  }
  if (f.mutableBackend().addLandmarks(blocks) != Status::kOk) { std::cerr << "addLandmarks failed\n"; return 1; }
  const int per_frame = std::max(1, static_cast<int>(rate / frame_rate + 0.5));
  double step_ms = 0.0, flush_ms = 0.0;
  int frames = 0;
  for (int i = 0; i < samples; ++i) {
    t += dt;
    const ImuSample m = sample(t);
    auto t0 = Clock::now();
    if (f.addImu(m) != Status::kOk) { std::cerr << "addImu failed\n"; return 1; }
    step_ms += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if ((i + 1) % per_frame == 0) {
      t0 = Clock::now();
      if (f.predictTo(t) != Status::kOk) { std::cerr << "predictTo failed\n"; return 1; }
      flush_ms += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
      ++frames;
    }
  }
  const double per_sample = step_ms / samples, per_flush = frames ? flush_ms / frames : 0.0;
  std::printf("| motion model | backend | K | samples | per-sample step ms | per-frame flush ms | per sample incl. flush ms |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  std::printf("| %s | %s | %d | %d | %.4f | %.3f | %.4f |\n", toString(s.motion_model), f.backend().name(), K, samples,
              per_sample, per_flush, per_sample + per_flush / per_frame);
  return 0;
}
