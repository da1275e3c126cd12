// Image-flow benchmark: ImageFlowTracker's time per frame at 640 x 480 (one
// thread: cv::setNumThreads(1); thread CPU time and wall time) on rendered
// frames of a band-limited texture moving by a known, slowly varying affine
// flow, with the accuracy of the same run (RMS error of the flow at the
// pixel, mean NEES of the six parameters), for a few settings; and the grey
// conversion of each encoding. Prints markdown tables.
//
//   hapi_frontend_flow_bench [--frames N] [--noise GREY_LEVELS]
#include "bench_clock.hpp"
#include "flow_texture.hpp"

#include "hapi_frontend/grey_convert.hpp"
#include "hapi_frontend/image_flow_tracker.hpp"

#include <Eigen/Dense>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include <chrono>
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

// Frame k shows the texture under the accumulated affine motion; the flow
// between frames varies smoothly (0.5-2 px/frame, gradients ~0.5 %/frame).
Sequence render(int frames, double noise) {
  const hapi_frontend_test::WaveTexture tex(5);
  std::mt19937 rng(9);
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
    const double a[6] = {t(0), t(1), m(0, 0) - 1, m(0, 1), m(1, 0), m(1, 1) - 1};
    s.frames.push_back(tex.renderAffine(kW, kH, cu, cv_, a, noise, &rng));
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

void conversions() {
  const cv::Mat grey = render(1, 0).frames[0];
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
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--frames")) frames = std::max(2, std::atoi(argv[i + 1]));
    else if (!std::strcmp(argv[i], "--noise")) noise = std::atof(argv[i + 1]);
    else {
      std::fprintf(stderr, "usage: hapi_frontend_flow_bench [--frames N] [--noise GREY_LEVELS]\n");
      return 2;
    }
  }
  cv::setNumThreads(1);
  const Sequence s = render(frames, noise);
  std::printf("ImageFlowTracker, %dx%d, %d frames, noise %.1f grey levels, pixel = image centre, one thread\n\n", kW,
              kH, frames, noise);
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
  conversions();
  return 0;
}
