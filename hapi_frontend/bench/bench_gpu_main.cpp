// hapi_frontend_gpu_bench: CPU reference vs CUDA, same frames, one run.
//  * ORB: OrbCpuCore (one thread) vs OrbCudaCore; host wall time per image
//    and per-stage GPU times from CUDA events (upload included / excluded).
//  * Stereo matcher: stereo_match_core vs StereoMatchCuda on the ORB
//    features of the same stereo pairs, for several feature counts.
//  * Identity of the GPU output with the CPU output on every frame.
// Medians over all frames; prints a Markdown table for docs/BENCHMARKS.md.
//   hapi_frontend_gpu_bench [--pairs 120] [--width 640] [--height 480]
//                           [--features 200] [--threshold 20] [--dir PGM_FOLDER]
#include "hapi_frontend/cuda/orb_cuda.hpp"
#include "hapi_frontend/cuda/stereo_match_cuda.hpp"
#include "hapi_frontend/orb_core.hpp"
#include "hapi_frontend/stereo_match_core.hpp"

#include "gpu/frames.hpp"
#include "gpu/orb_compare.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

using namespace hapi_frontend;
using Clock = std::chrono::steady_clock;

namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

ImageView8 view(const gpu_test::Frame& f) { return {f.pixels.data(), f.width, f.height, f.width}; }

const double kRectF[9] = {0, 0, 0, 0, 0, -1, 0, 1, 0};

void row(const char* name, double cpu, double gpu) {
  if (cpu > 0)
    std::printf("| %-44s | %9.3f | %9.3f | %7.1fx |\n", name, cpu, gpu, gpu > 0 ? cpu / gpu : 0.0);
  else
    std::printf("| %-44s | %9s | %9.3f | %8s |\n", name, "", gpu, "");
}

}  // namespace

int main(int argc, char** argv) {
  int pairs = 120, width = 640, height = 480, features = 200, threshold = OrbParams().fast_threshold;
  std::string dir;
  for (int a = 1; a + 1 < argc; a += 2) {
    const std::string k = argv[a];
    if (k == "--pairs") pairs = std::atoi(argv[a + 1]);
    else if (k == "--width") width = std::atoi(argv[a + 1]);
    else if (k == "--height") height = std::atoi(argv[a + 1]);
    else if (k == "--features") features = std::atoi(argv[a + 1]);
    else if (k == "--threshold") threshold = std::atoi(argv[a + 1]);
    else if (k == "--dir") dir = argv[a + 1];
    else {
      std::fprintf(stderr, "unknown option %s\n", k.c_str());
      return 2;
    }
  }
  std::string info;
  if (!cudaDeviceAvailable(&info)) {
    std::fprintf(stderr, "no CUDA device: %s\n", info.c_str());
    return 1;
  }

  // Frames: procedural stereo pairs (left, right interleaved) or a PGM folder.
  std::vector<gpu_test::Frame> frames;
  if (!dir.empty()) {
    for (const std::string& p : gpu_test::listPgm(dir)) {
      gpu_test::Frame f;
      std::string err;
      if (!gpu_test::loadPgm(p, f, &err)) {
        std::fprintf(stderr, "%s\n", err.c_str());
        return 1;
      }
      frames.push_back(std::move(f));
    }
    if (frames.size() < 2) {
      std::fprintf(stderr, "need >= 2 PGM frames in %s\n", dir.c_str());
      return 1;
    }
    frames.resize(frames.size() & ~size_t(1));  // consecutive files = (left, right)
  } else {
    for (int k = 0; k < pairs; ++k) {
      gpu_test::Frame l, r;
      gpu_test::renderStereoPair(width, height, 9000 + k, 48, 3, l, r);
      frames.push_back(std::move(l));
      frames.push_back(std::move(r));
    }
  }
  const int n_img = static_cast<int>(frames.size());
  OrbParams op;
  op.n_features = features;
  op.fast_threshold = threshold;
  std::printf("device: %s\nframes: %d images (%dx%d, %s), ORB N=%d, %d levels, scale %.1f, FAST t=%d\n\n", info.c_str(),
              n_img, frames[0].width, frames[0].height, dir.empty() ? "procedural stereo pairs" : dir.c_str(), features,
              op.n_levels, op.scale_factor, op.fast_threshold);

  OrbCpuCore cpu(op);
  OrbCudaCore gpu(op);
  gpu.setTiming(true);

  // CPU ORB.
  std::vector<OrbResult> cpu_res(n_img);
  std::vector<double> t_cpu;
  for (int i = 0; i < std::min(n_img, 5); ++i) cpu.extract(view(frames[i]));  // warm caches
  for (int i = 0; i < n_img; ++i) {
    const auto t0 = Clock::now();
    cpu_res[i] = cpu.extract(view(frames[i]));
    t_cpu.push_back(msSince(t0));
  }
  // GPU ORB (first calls allocate and load the module: warm up).
  for (int i = 0; i < std::min(n_img, 10); ++i) gpu.extract(view(frames[i]));
  std::vector<double> t_wall, t_up, t_pyr, t_det, t_sel, t_desc, t_down, t_tot, t_noup;
  gpu_test::OrbIdentity ident;
  for (int i = 0; i < n_img; ++i) {
    const auto t0 = Clock::now();
    const OrbResult r = gpu.extract(view(frames[i]));
    t_wall.push_back(msSince(t0));
    const OrbCudaTimes& t = gpu.lastTimes();
    t_up.push_back(t.upload_ms);
    t_pyr.push_back(t.pyramid_ms);
    t_det.push_back(t.detect_ms);
    t_sel.push_back(t.select_ms);
    t_desc.push_back(t.describe_ms);
    t_down.push_back(t.download_ms);
    t_tot.push_back(t.total_ms);
    t_noup.push_back(t.total_ms - t.upload_ms);
    const gpu_test::OrbIdentity id = gpu_test::compareOrb(cpu_res[i], r);
    ident.n_ref += id.n_ref;
    ident.n_test += id.n_test;
    ident.identical += id.identical;
  }
  // Timing disabled: wall time without the event records.
  gpu.setTiming(false);
  std::vector<double> t_wall_nt;
  for (int i = 0; i < n_img; ++i) {
    const auto t0 = Clock::now();
    gpu.extract(view(frames[i]));
    t_wall_nt.push_back(msSince(t0));
  }

  std::printf("ORB identity GPU vs CPU: %d / %d keypoints+descriptors identical (%.3f %%), GPU total %d\n\n",
              ident.identical, ident.n_ref, ident.percent(), ident.n_test);
  std::printf("| ORB, one image (median over %d images) [ms]     |       CPU |       GPU | CPU/GPU |\n", n_img);
  std::printf("|----------------------------------------------|-----------|-----------|---------|\n");
  row("extract, host wall (staging+upload+sync+copy)", median(t_cpu), median(t_wall_nt));
  row("extract, host wall with per-stage events", median(t_cpu), median(t_wall));
  row("GPU: upload (pinned H2D)", 0, median(t_up));
  row("GPU: pyramid + 5x5 smoothing", 0, median(t_pyr));
  row("GPU: FAST-9 + 3x3 NMS + compaction", 0, median(t_det));
  row("GPU: rank-key radix sort (quota select)", 0, median(t_sel));
  row("GPU: orientation + steered BRIEF", 0, median(t_desc));
  row("GPU: download", 0, median(t_down));
  row("GPU events total, upload included", median(t_cpu), median(t_tot));
  row("GPU events total, upload excluded", median(t_cpu), median(t_noup));

  // Matcher: same stereo pairs, features from the CPU core at several N.
  StereoMatchCuda mg;
  MatchCoreParams mp;
  std::printf("\n| stereo matching, one pair (median over %d pairs) [ms] |       CPU |       GPU | CPU/GPU |\n",
              n_img / 2);
  std::printf("|----------------------------------------------|-----------|-----------|---------|\n");
  for (int nf : {features, 1000, 4000}) {
    OrbParams p2 = op;
    p2.n_features = nf;
    OrbCpuCore c2(p2);
    std::vector<double> tc, tg, tge;
    long long n_match = 0, n_kp = 0;
    int mismatched_pairs = 0;
    for (int k = 0; k + 1 < n_img; k += 2) {
      const OrbResult a = nf == features ? cpu_res[k] : c2.extract(view(frames[k]));
      const OrbResult b = nf == features ? cpu_res[k + 1] : c2.extract(view(frames[k + 1]));
      std::vector<float> pa, pb;
      for (const auto& kp : a.keypoints) pa.insert(pa.end(), {kp.x, kp.y});
      for (const auto& kp : b.keypoints) pb.insert(pb.end(), {kp.x, kp.y});
      const int na = static_cast<int>(a.keypoints.size()), nb = static_cast<int>(b.keypoints.size());
      n_kp += na;
      auto t0 = Clock::now();
      const auto rc = stereo_match_core(a.descriptors.data(), pa.data(), na, b.descriptors.data(), pb.data(), nb,
                                        kOrbDescBytes, kRectF, mp);
      tc.push_back(msSince(t0));
      if (k == 0) mg.match(a.descriptors.data(), pa.data(), na, b.descriptors.data(), pb.data(), nb, kOrbDescBytes, kRectF, mp);
      mg.setTiming(true);
      t0 = Clock::now();
      const auto rg = mg.match(a.descriptors.data(), pa.data(), na, b.descriptors.data(), pb.data(), nb, kOrbDescBytes,
                               kRectF, mp);
      tg.push_back(msSince(t0));
      tge.push_back(mg.lastTimes().match_ms);
      mg.setTiming(false);
      n_match += static_cast<long long>(rc.size());
      bool same = rc.size() == rg.size();
      for (size_t m = 0; same && m < rc.size(); ++m)
        same = rc[m].left == rg[m].left && rc[m].right == rg[m].right && rc[m].distance == rg[m].distance;
      mismatched_pairs += !same;
    }
    char name[96];
    std::snprintf(name, sizeof(name), "match, ~%lld x %lld kps, host wall", n_kp / (n_img / 2), n_kp / (n_img / 2));
    row(name, median(tc), median(tg));
    std::snprintf(name, sizeof(name), "  (GPU kernels only, events; %lld matches/pair)", n_match / (n_img / 2));
    row(name, median(tc), median(tge));
    if (mismatched_pairs) std::printf("!! %d pairs with GPU matches != CPU matches\n", mismatched_pairs);
    else std::printf("|   (GPU matches identical to CPU on all %d pairs) | | | |\n", n_img / 2);
  }
  return 0;
}
