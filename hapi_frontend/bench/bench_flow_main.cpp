// Image-flow benchmark: ImageFlowTracker's time per frame at 640 x 480 (one
// thread: cv::setNumThreads(1); thread CPU time and wall time) on rendered
// frames of a band-limited texture moving by a known, slowly varying affine
// flow, with the accuracy of the same run (RMS error of the flow at the
// pixel, mean NEES of the six parameters), for a few settings; and the grey
// conversion of each encoding. Then the backends (use_gpu) in one run on the
// same frames: wall time per frame from the host image to the affine result
// (for CUDA: upload, pyramid, corners, LK, download and the fit on the CPU),
// p50/p99/max over a second pass (the first warms up), accuracy against the
// truth and the largest CUDA - CPU difference; the CUDA row only with a
// device. Prints markdown tables. Textures: "waves"
// (test/flow_texture.hpp) or, when built with hapi_sim, "skin" (its
// procedural skin, faint: +-7 grey levels of mottling).
//
//   hapi_frontend_flow_bench [--frames N] [--noise GREY_LEVELS] [--texture waves|skin] [--backends-only 1]
#include "bench_clock.hpp"
#include "flow_texture.hpp"

#include "hapi_frontend/grey_convert.hpp"
#include "hapi_frontend/image_flow_tracker.hpp"

#include <Eigen/Dense>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#ifdef HAPI_FLOW_BENCH_SKIN
#include <hapi_sim/scene.hpp>
#endif

#include <algorithm>
#include <chrono>
#include <functional>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

using namespace hapi_frontend;
using hapi_frontend_bench::med;
using hapi_frontend_bench::threadCpuMs;

namespace {

constexpr int kW = 640, kH = 480;

struct Sequence {
  std::vector<cv::Mat> frames;
  std::vector<Eigen::Matrix<double, 6, 1>> truth;  // flow from frame k-1 to k about the centre
};

// Grey level of the scene at a point [px of the reference frame].
using Field = std::function<double(double, double)>;

// Frame k shows the field under the accumulated affine motion (each pixel
// the mean of 2 x 2 samples: the pixel's area, so fine texture does not
// alias); the flow between frames varies smoothly (0.5-2 px/frame,
// gradients ~0.5 %/frame).
Sequence render(const Field& field, int frames, double noise) {
  std::mt19937 rng(9);
  std::normal_distribution<double> grain(0.0, noise > 0 ? noise : 1.0);
  const double cu = 0.5 * (kW - 1), cv_ = 0.5 * (kH - 1);
  Sequence s;
  Eigen::Matrix2d m = Eigen::Matrix2d::Identity();
  Eigen::Vector2d t = Eigen::Vector2d::Zero();
  for (int k = 0; k < frames; ++k) {
    Eigen::Matrix<double, 6, 1> f;
    f << 1.5 * std::cos(0.2 * k), 1.0 * std::sin(0.13 * k), 0.004 * std::sin(0.1 * k), -0.003, 0.003,
        0.004 * std::cos(0.07 * k);
    if (k > 0) {
      // Point p of frame k-1 moves to c + t_f + (I + G)(p - c).
      Eigen::Matrix2d g;
      g << 1 + f(2), f(3), f(4), 1 + f(5);
      t = f.head<2>() + g * t;
      m = g * m;
    }
    s.truth.push_back(f);
    const Eigen::Matrix2d inv = m.inverse();
    cv::Mat img(kH, kW, CV_8UC1);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        double g = 0;
        for (double oy : {-0.25, 0.25})
          for (double ox : {-0.25, 0.25}) {
            const Eigen::Vector2d src = Eigen::Vector2d(cu, cv_) + inv * (Eigen::Vector2d(x + ox - cu, y + oy - cv_) - t);
            g += 0.25 * field(src.x(), src.y());
          }
        if (noise > 0) g += grain(rng);
        img.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(std::lround(g));
      }
    s.frames.push_back(img);
  }
  return s;
}

void runConfig(const char* name, const ImageFlowParams& p, const Sequence& s) {
  ImageFlowTracker tracker(p);
  std::vector<double> cpu, wall;
  double se = 0, nees = 0;
  int ok = 0, inliers = 0;
  ImageFlowResult r;
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    const double c0 = threadCpuMs();
    const auto w0 = std::chrono::steady_clock::now();
    tracker.process(s.frames[k], static_cast<std::int64_t>(k) * 25'000'000, &r);
    wall.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - w0).count());
    cpu.push_back(threadCpuMs() - c0);
    if (r.status != FlowStatus::kOk) continue;
    ++ok;
    inliers += r.inliers;
    const Eigen::Matrix<double, 6, 1> e = r.affine - s.truth[k];
    se += e.head<2>().squaredNorm();
    nees += e.dot(r.covariance.ldlt().solve(e));
  }
  std::vector<double> sorted = cpu;
  std::sort(sorted.begin(), sorted.end());
  std::printf("| %s | %.2f | %.2f | %.2f | %.2f | %d/%zu | %.0f | %.4f | %.2f |\n", name, med(cpu),
              sorted[sorted.size() * 9 / 10], sorted.back(), med(wall), ok, s.frames.size() - 1,
              ok ? double(inliers) / ok : 0.0, ok ? std::sqrt(se / ok) : 0.0, ok ? nees / ok : 0.0);
}

double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * v.size()))];
}

// One backend over the sequence, twice (the first pass warms up: CUDA
// allocations, caches); the second pass's per-frame wall times and results.
struct BackendRun {
  std::vector<double> wall_ms;
  std::vector<ImageFlowResult> results;
};

BackendRun runBackend(ImageFlowTracker& tracker, const Sequence& s) {
  BackendRun run;
  ImageFlowResult r;
  for (int pass = 0; pass < 2; ++pass) {
    tracker.reset();
    run.wall_ms.clear();
    run.results.clear();
    for (std::size_t k = 0; k < s.frames.size(); ++k) {
      const auto w0 = std::chrono::steady_clock::now();
      tracker.process(s.frames[k], static_cast<std::int64_t>(k + 1) * 25'000'000, &r);
      run.wall_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - w0).count());
      run.results.push_back(r);
    }
  }
  return run;
}

void backends(const ImageFlowParams& p, const Sequence& s) {
  ImageFlowParams pg = p;
  pg.use_gpu = true;
  ImageFlowTracker cpu(p), gpu(pg);
  std::printf("\nBackends, default settings, frame 640x480 -> affine result, wall time of process() over the second "
              "of two passes; CUDA: %s\n\n", gpu.backendStatus().c_str());
  std::printf("| backend | wall ms p50 | p99 | max | valid | RMS error at pixel [px] | max abs CUDA - CPU: flow [px] "
              "| gradient [1/frame] |\n| --- | --- | --- | --- | --- | --- | --- | --- |\n");
  const BackendRun rc = runBackend(cpu, s);
  BackendRun rg;
  if (gpu.usingGpu()) rg = runBackend(gpu, s);
  for (const BackendRun* run : {&rc, static_cast<const BackendRun*>(&rg)}) {
    if (run->results.empty()) continue;
    double se = 0, dflow = 0, dgrad = 0;
    int ok = 0;
    for (std::size_t k = 0; k < run->results.size(); ++k) {
      const ImageFlowResult& r = run->results[k];
      if (r.status != FlowStatus::kOk) continue;
      ++ok;
      se += (r.affine - s.truth[k]).head<2>().squaredNorm();
      if (run == &rg && rc.results[k].status == FlowStatus::kOk) {
        const Eigen::Matrix<double, 6, 1> d = (r.affine - rc.results[k].affine).cwiseAbs();
        dflow = std::max(dflow, d.head<2>().maxCoeff());
        dgrad = std::max(dgrad, d.tail<4>().maxCoeff());
      }
    }
    const bool is_gpu = run == &rg;
    std::printf("| %s | %.3f | %.3f | %.3f | %d/%zu | %.4f | %s | %s |\n", is_gpu ? "CUDA" : "CPU (1 thread)",
                percentile(run->wall_ms, 0.5), percentile(run->wall_ms, 0.99),
                *std::max_element(run->wall_ms.begin(), run->wall_ms.end()), ok, s.frames.size() - 1,
                ok ? std::sqrt(se / ok) : 0.0, is_gpu ? std::to_string(dflow).c_str() : "-",
                is_gpu ? std::to_string(dgrad).c_str() : "-");
  }
}

void conversions(const Field& field) {
  const cv::Mat grey = render(field, 1, 0).frames[0];
  struct Case {
    const char* encoding;
    cv::Mat m;
  };
  cv::Mat bgr, bgra, m16, f32;
  cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
  cv::cvtColor(grey, bgra, cv::COLOR_GRAY2BGRA);
  grey.convertTo(m16, CV_16U, 16.0);
  grey.convertTo(f32, CV_32F, 0.01);
  const Case cases[] = {{"mono8", grey}, {"mono16", m16}, {"bgr8", bgr}, {"bgra8", bgra}, {"32FC1", f32}};
  std::printf("\n| encoding | convertToGrey CPU ms (median of 50) |\n| --- | --- |\n");
  for (const Case& c : cases) {
    RawImageView v;
    v.encoding = c.encoding;
    v.width = c.m.cols;
    v.height = c.m.rows;
    v.step = static_cast<std::uint32_t>(c.m.step[0]);
    v.data = c.m.data;
    v.size = c.m.step[0] * c.m.rows;
    std::vector<double> t;
    cv::Mat out;
    for (int i = 0; i < 50; ++i) {
      const double c0 = threadCpuMs();
      convertToGrey(v, 12, &out);
      t.push_back(threadCpuMs() - c0);
    }
    std::printf("| %s | %.3f |\n", c.encoding, med(t));
  }
}

}  // namespace

int main(int argc, char** argv) {
  int frames = 200;
  double noise = 2.0;
  std::string texture = "waves";
  bool backends_only = false;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--frames")) frames = std::max(2, std::atoi(argv[i + 1]));
    else if (!std::strcmp(argv[i], "--noise")) noise = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--texture")) texture = argv[i + 1];
    else if (!std::strcmp(argv[i], "--backends-only")) backends_only = std::atoi(argv[i + 1]) != 0;
    else {
      std::fprintf(stderr, "usage: hapi_frontend_flow_bench [--frames N] [--noise GREY_LEVELS] [--texture waves|skin] "
                           "[--backends-only 1]\n");
      return 2;
    }
  }
  cv::setNumThreads(1);
  Field field;
  const hapi_frontend_test::WaveTexture waves(5);
#ifdef HAPI_FLOW_BENCH_SKIN
  // hapi_sim's skin (texel 0.2 mm) seen at 0.4 mm per pixel (the imaging
  // camera at ~22 cm with f ~ 550 px).
  hapi_sim::Texture skin;
  skin.texels = hapi_sim::makeSkinTexture(2 * kW + 400, 2 * kH + 400, 0.2e-3);
  if (texture == "skin") field = [&](double x, double y) { return skin.sample(2 * x + 200, 2 * y + 200); };
#endif
  if (texture == "waves") field = [&](double x, double y) { return waves.at(x, y); };
  if (!field) {
    std::fprintf(stderr, "texture '%s' unknown or not built (skin needs hapi_sim)\n", texture.c_str());
    return 2;
  }
  const Sequence s = render(field, frames, noise);
  if (backends_only) {
    backends(ImageFlowParams(), s);
    return 0;
  }
  std::printf("ImageFlowTracker, %dx%d, %d frames of the %s texture, noise %.1f grey levels, pixel = image centre, "
              "one thread\n\n", kW, kH, frames, texture.c_str(), noise);
  std::printf("| settings | CPU ms median | p90 | max | wall ms median | valid | inliers | RMS error at pixel [px] | "
              "NEES (6 dof) |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
  ImageFlowParams p;
  runConfig("defaults (radius 48, 120 features, 3 levels, window 21)", p, s);
  ImageFlowParams small = p;
  small.search_radius = 32;
  small.max_features = 60;
  runConfig("radius 32, 60 features", small, s);
  ImageFlowParams big = p;
  big.search_radius = 96;
  big.max_features = 300;
  runConfig("radius 96, 300 features", big, s);
  ImageFlowParams two = p;
  two.pyramid_levels = 2;
  two.lk_window = 15;
  runConfig("2 levels, window 15", two, s);
  conversions(field);
  backends(p, s);
  return 0;
}
