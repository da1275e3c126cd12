// Front-end CPU benchmark: renders globe stereo pairs along the sim
// trajectory (hapi_sim), then times StereoPipeline per stage on ONE core
// (cv::setNumThreads(1); pin the process with taskset for a clean number).
// Prints a markdown table of per-stage medians and frames/s for each
// configuration, plus the accuracy of the same run as a sanity check.
//
//   hapi_frontend_bench [--frames N] [--reps R] [--width W --height H]
#include "bench_clock.hpp"
#include "globe_eval.hpp"

#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

using namespace hapi_frontend;
using namespace hapi_frontend::globe_eval;
using hapi_frontend_bench::med;
using hapi_frontend_bench::threadCpuMs;

namespace {
struct Row {
  std::string name;
  std::vector<double> convert, det_l, det_r, undist, match, refine, tri, total, cpu;
  int landmarks = 0, wrong = 0, frames = 0;
  std::vector<double> rel;
};

Row runConfig(const std::string& name, const PipelineParams& pp, const GlobeWorld& w,
              const std::vector<GlobePair>& pairs, int reps) {
  Row row;
  row.name = name;
  StereoPipeline pipe(pp);
  const std::string e = pipe.setCalibration(copyCameraInfo(w.rig.leftInfo()), copyCameraInfo(w.rig.rightInfo()));
  if (!e.empty()) {
    std::fprintf(stderr, "calibration: %s\n", e.c_str());
    std::exit(1);
  }
  StereoFrameResult r;
  pipe.process(pairs[0].left, pairs[0].right, cv::Mat(), &r);  // warm-up (allocations)
  for (int rep = 0; rep < reps; ++rep)
    for (const GlobePair& p : pairs) {
      const double c0 = threadCpuMs();
      const std::string err = pipe.process(p.left, p.right, cv::Mat(), &r);
      row.cpu.push_back(threadCpuMs() - c0);
      if (!err.empty()) {
        std::fprintf(stderr, "process: %s\n", err.c_str());
        std::exit(1);
      }
      const StageTimesMs& t = r.times;
      row.convert.push_back(t.convert);
      row.det_l.push_back(t.detect_left);
      row.det_r.push_back(t.detect_right);
      row.undist.push_back(t.undistort);
      row.match.push_back(t.match);
      row.refine.push_back(t.refine);
      row.tri.push_back(t.triangulate);
      row.total.push_back(t.total);
      if (rep == 0) {
        const FrameStats s = evaluate(w, p, r);
        row.landmarks += s.landmarks;
        row.wrong += s.wrong;
        ++row.frames;
        row.rel.insert(row.rel.end(), s.rel_err.begin(), s.rel_err.end());
      }
    }
  return row;
}
}  // namespace

int main(int argc, char** argv) {
  int frames = 20, reps = 5;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--frames")) frames = std::max(1, std::atoi(argv[i + 1]));
    else if (!std::strcmp(argv[i], "--reps")) reps = std::max(1, std::atoi(argv[i + 1]));
    else {
      std::fprintf(stderr, "usage: %s [--frames N] [--reps R]\n", argv[0]);
      return 2;
    }
  }
  cv::setNumThreads(1);  // one core: no OpenCV worker threads (resize, matchTemplate, AKAZE)
  GlobeWorld w;
  std::vector<GlobePair> pairs;
  for (int f = 0; f < frames; ++f) pairs.push_back(renderPair(w, 0.5 + 1.3 * f, 900 + f));
  std::printf("globe pairs: %d frames %dx%d (texture: %s), %d repetitions, 1 thread\n\n", frames,
              pairs[0].left.cols, pairs[0].left.rows, w.scene.texture_source.c_str(), reps);

  std::vector<Row> rows;
  PipelineParams orb;
  orb.landmarks_per_frame = 200;
  rows.push_back(runConfig("ORB N=200", orb, w, pairs, reps));
  PipelineParams orb_noref = orb;
  orb_noref.refine_subpixel = false;
  orb_noref.pixel_sigma = 0.37;
  rows.push_back(runConfig("ORB N=200, no refinement", orb_noref, w, pairs, reps));
  PipelineParams orb_half = orb;
  orb_half.downscale = 2.0;
  rows.push_back(runConfig("ORB N=200, downscale 2", orb_half, w, pairs, reps));
  PipelineParams akaze = orb;
  akaze.detector = "akaze";
  rows.push_back(runConfig("AKAZE N=200", akaze, w, pairs, reps));

  std::printf("| configuration | convert | detect L | detect R | undistort | match | refine | triangulate | total | frames/s | CPU ms | frames/s (CPU) | landmarks/frame | wrong | median err/depth |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    const double tot = med(r.total);
    std::printf("| %s | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.1f | %.2f | %.1f | %.1f | %.2f %% | %.3f %% |\n",
                r.name.c_str(), med(r.convert), med(r.det_l), med(r.det_r), med(r.undist), med(r.match),
                med(r.refine), med(r.tri), tot, tot > 0 ? 1000.0 / tot : 0.0, med(r.cpu), 1000.0 / std::max(1e-9, med(r.cpu)),
                static_cast<double>(r.landmarks) / r.frames, 100.0 * r.wrong / std::max(1, r.landmarks),
                100.0 * median(r.rel));
  }
  std::printf("\n(per-stage medians of wall time in ms over %d frames x %d repetitions; total = whole process() call;\n"
              " CPU ms = median thread CPU time of process(), insensitive to other load on the machine)\n", frames, reps);
  return 0;
}
