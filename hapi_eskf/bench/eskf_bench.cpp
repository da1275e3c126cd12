// hapi_eskf_bench: per-stage timings of the filter core for a list of
// pool sizes K, CPU reference and CUDA backend in the same run, with the
// device's measured ceilings and the floor of the C <- C - A A^T step.
//   hapi_eskf_bench [--k 1000,2000,...] [--iters 50] [--cpu-iters 3]
//                   [--backend cpu|cuda|both] [--precision fp64|fp32]
//                   [--cpu-max-k 2000] [--visible 200] [--fresh 20] [--rank-reps 3]
//                   [--cuda-rank-update auto|syrk|gemm|recursive]
//                   [--cuda-solve auto|trsm|inverse] [--cuda-stage-times]
// The --precision and --cuda-* flags set the EskfSettings fields of the same
// names (eskf_settings.def) for the CUDA backend (device 0, where the
// ceilings are measured). Builds and runs without a GPU (CPU rows only).
#include "device_ceilings.hpp"
#include "scenario.hpp"

#include "hapi_eskf/covariance_backend.hpp"
#ifdef HAPI_ESKF_BENCH_WITH_CUDA
#include "hapi_eskf/cuda/cuda_backend.hpp"
#include "../src/cuda/stage_times.hpp"
#endif

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>
#include <string>
#include <vector>

using namespace hapi_eskf;
using namespace hapi_eskf::bench;

namespace {

struct Options {
  std::vector<int> ks = {1000, 2000, 4000, 8000, 16000, 32000};
  int iters = 50, cpu_iters = 3, warmup = 3, cpu_warmup = 1;
  bool cpu = true, cuda = true;
  // precision, cuda_rank_update, cuda_solve, cuda_stage_times.
  EskfSettings backend;
  int cpu_max_k = 2000;
  int visible = 200, fresh = 20;
  int rank_reps = 3;
};

[[noreturn]] void usage(const char* msg) {
  std::fprintf(stderr,
               "error: %s\nusage: hapi_eskf_bench [--k 1000,2000] [--iters N] [--cpu-iters N] [--backend cpu|cuda|both]\n"
               "       [--precision fp64|fp32] [--cpu-max-k K] [--visible L] [--fresh M] [--rank-reps N]\n"
               "       [--cuda-rank-update auto|syrk|gemm|recursive] [--cuda-solve auto|trsm|inverse] [--cuda-stage-times]\n",
               msg);
  std::exit(2);
}

int toInt(const char* s, const char* flag) {
  char* end = nullptr;
  const long v = std::strtol(s, &end, 10);
  if (end == s || *end != '\0' || v < 0 || v > 10000000) usage((std::string("bad value for ") + flag).c_str());
  return static_cast<int>(v);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> const char* {
      if (i + 1 >= argc) usage(("missing value after " + a).c_str());
      return argv[++i];
    };
    if (a == "--k") {
      o.ks.clear();
      std::stringstream ss(next());
      std::string item;
      while (std::getline(ss, item, ',')) o.ks.push_back(toInt(item.c_str(), "--k"));
      if (o.ks.empty()) usage("--k needs at least one value");
    } else if (a == "--iters") {
      o.iters = toInt(next(), "--iters");
    } else if (a == "--cpu-iters") {
      o.cpu_iters = toInt(next(), "--cpu-iters");
    } else if (a == "--backend") {
      const std::string v = next();
      if (v == "cpu") o.cuda = false;
      else if (v == "cuda") o.cpu = false;
      else if (v != "both") usage("--backend must be cpu, cuda or both");
    } else if (a == "--precision" || a == "--cuda-rank-update" || a == "--cuda-solve") {
      std::string field = a.substr(2);  // the settings field of the same name
      std::replace(field.begin(), field.end(), '-', '_');
      const std::string e = setFieldFromText(&o.backend, field, next());
      if (!e.empty()) usage(e.c_str());
    } else if (a == "--cuda-stage-times") {
      o.backend.cuda_stage_times = true;
    } else if (a == "--cpu-max-k") {
      o.cpu_max_k = toInt(next(), "--cpu-max-k");
    } else if (a == "--visible") {
      o.visible = toInt(next(), "--visible");
    } else if (a == "--rank-reps") {
      o.rank_reps = toInt(next(), "--rank-reps");
    } else if (a == "--fresh") {
      o.fresh = toInt(next(), "--fresh");
    } else {
      usage(("unknown flag " + a).c_str());
    }
  }
  if (o.iters < 1 || o.cpu_iters < 1) usage("--iters and --cpu-iters must be >= 1");
  const std::string bad = o.backend.validate();
  if (!bad.empty()) usage(bad.c_str());
  for (int k : o.ks)
    if (k < o.visible + o.fresh) usage("every K must be >= visible + fresh");
  return o;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Row {
  std::string backend;
  int K = 0, iters = 0;
  bool ok = false;
  std::string note;
  double assoc = 0, removal = 0, addition = 0, predict = 0, update = 0, total = 0, bookkeeping = 0;
  double mem_gb = 0;
  double moved = 0;  // landmarks moved into freed slots per removal (median)
  int n_updated = 0;
  // Medians of the update's device stages (--cuda-stage-times, CUDA rows).
  std::vector<double> stages;
};

const char* const kStageNames[] = {"upload", "gather", "S", "potrf+readback", "host wait 1", "A = P L^-T",
                                   "y, dx + readback", "host wait 2", "rank update"};
constexpr int kStageCount = 9;

Row run(const std::string& name, std::unique_ptr<CovarianceBackend> b, int K, int iters, int warmup,
        const Options& o) {
  Row r;
  r.backend = name;
  r.K = K;
  if (!b) {
    r.note = "backend not created";
    return r;
  }
  Scenario sc(std::move(b), K, o.visible, o.fresh, 1234u + K);
  if (!sc.fill()) {
    r.note = "filling the pool failed";
    return r;
  }
  r.note.clear();
  std::vector<double> a, rm, ad, pr, up, to, bk, nu, mv;
  bool ok = true;
  std::vector<std::vector<double>> stage_samples(kStageCount);
  for (int i = 0; i < warmup + iters; ++i) {
#ifdef HAPI_ESKF_BENCH_WITH_CUDA
    if (i == warmup) {  // drop the warm-up ones
      cuda::takeUpdateStageTimes();
    }
#endif
    const StageTimes t = sc.iterate();
    if (!t.ok) {
      ok = false;
      r.note = "iteration " + std::to_string(i) + " failed at " + t.failure;
      break;
    }
    if (i < warmup) continue;
    a.push_back(t.association);
    rm.push_back(t.removal);
    ad.push_back(t.addition);
    pr.push_back(t.predict);
    up.push_back(t.update);
    to.push_back(t.total);
    bk.push_back(t.removal + t.addition);
    nu.push_back(t.n_updated);
    mv.push_back(t.removal_moved_landmarks);
  }
#ifdef HAPI_ESKF_BENCH_WITH_CUDA
  for (const cuda::UpdateStageTimes& u : cuda::takeUpdateStageTimes()) {
    const double v[kStageCount] = {u.upload, u.gather, u.innovation_cov, u.factor, u.host_check1,
                                   u.trsm, u.solve, u.host_check2, u.rank_update};
    for (int k = 0; k < kStageCount; ++k) stage_samples[k].push_back(v[k]);
  }
#endif
  if (!stage_samples[0].empty())
    for (int k = 0; k < kStageCount; ++k) r.stages.push_back(median(stage_samples[k]));
  r.ok = ok;
  r.iters = iters;
  r.mem_gb = sc.backend().memoryBytes() / 1e9;  // after the run: work buffers have grown to their size
  r.assoc = median(a);
  r.removal = median(rm);
  r.addition = median(ad);
  r.predict = median(pr);
  r.update = median(up);
  r.total = median(to);
  r.bookkeeping = median(bk);
  r.n_updated = static_cast<int>(median(nu));
  r.moved = median(mv);
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // progress survives a crash or a timeout
  const Options o = parse(argc, argv);
  const bool fp32 = o.backend.precision == Precision::kFp32;
  std::printf("hapi_eskf_bench: L = %d visible (update), %d new + %d evicted per iteration, descriptors %d B\n",
              o.visible, o.fresh, o.fresh, Scenario::kDescLen);
  std::printf("stage times are medians over the measured iterations (after %d warm-up on CUDA, %d on CPU), in ms; "
              "total = predict + association + update + removal + addition\n",
              o.warmup, o.cpu_warmup);
  std::printf("CUDA variants: rank update %s, solve %s (auto = by size, the default); stage times %s\n",
              valueText(o.backend.cuda_rank_update).c_str(), valueText(o.backend.cuda_solve).c_str(),
              o.backend.cuda_stage_times ? "on" : "off");

  Ceilings ceil;
  std::string why;
  bool have_cuda = false;
  if (o.cuda) {
    have_cuda = measureCeilings(fp32, &ceil, &why);
    if (have_cuda) {
      std::printf("device: %s\nceilings: %s GEMM %.1f TFLOP/s (8192^3, random operands), D2D copy %.0f GB/s (read + write)\n",
                  ceil.device.c_str(), fp32 ? "FP32" : "FP64", ceil.gemm_tflops, ceil.copy_gbps);
    } else {
      std::printf("CUDA rows skipped: %s\n", why.c_str());
    }
  }

  std::vector<Row> rows;
  std::map<int, RankUpdateTiming> rank;
  for (int K : o.ks) {
    if (have_cuda) {
      const int n = stateDim(K, kCameraMotionDim);
      RankUpdateTiming rt;
      std::string w;
      if (measureRankUpdate(fp32, n, 3 * o.visible, o.rank_reps, &rt, &w)) rank[K] = rt;
      else std::printf("K=%d: isolated rank update not measured: %s\n", K, w.c_str());
#ifdef HAPI_ESKF_BENCH_WITH_CUDA
      std::string err;
      auto b = cuda::makeCudaBackend(K, Scenario::kDescLen, kCameraMotionDim, o.backend, &err);
      if (!b) {
        Row r;
        r.backend = std::string("cuda-") + toString(o.backend.precision);
        r.K = K;
        r.note = err;
        rows.push_back(r);
      } else {
        const std::string name = b->name();  // before the move (argument order is unspecified)
        rows.push_back(run(name, std::move(b), K, o.iters, o.warmup, o));
      }
#endif
    }
    if (o.cpu && K <= o.cpu_max_k) rows.push_back(run("cpu", makeCpuBackend(K, Scenario::kDescLen), K, o.cpu_iters, o.cpu_warmup, o));
    for (const Row& r : rows)
      if (r.K == K)
        std::printf("  K=%d %s: %s total %.3f ms\n", K, r.backend.c_str(), r.ok ? "ok" : r.note.c_str(), r.total);
  }

  std::printf("\n| backend | K | iters | association | removal | addition | predict | update | total | bookkeeping "
              "(rem+add) | memory GB | L used | moved per removal |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    if (!r.ok) {
      std::printf("| %s | %d | - | %s |\n", r.backend.c_str(), r.K, r.note.c_str());
      continue;
    }
    std::printf("| %s | %d | %d | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.2f | %d | %.0f |\n",
                r.backend.c_str(), r.K, r.iters, r.assoc, r.removal, r.addition, r.predict, r.update, r.total,
                r.bookkeeping, r.mem_gb, r.n_updated, r.moved);
  }

  // The update's device stages, where recorded (--cuda-stage-times).
  bool stage_header = false;
  for (const Row& r : rows) {
    if (r.stages.empty() || !r.ok) continue;
    if (!stage_header) {
      std::printf("\nupdate stages (median ms, events on the filter stream; sum vs the host-timed update):\n| backend | K |");
      for (const char* nm : kStageNames) std::printf(" %s |", nm);
      std::printf(" sum | update (host) |\n|---|---|");
      for (int k = 0; k <= kStageCount; ++k) std::printf("---|");
      std::printf("---|\n");
      stage_header = true;
    }
    std::printf("| %s | %d |", r.backend.c_str(), r.K);
    double sum = 0;
    for (double v : r.stages) {
      std::printf(" %.3f |", v);
      sum += v;
    }
    std::printf(" %.3f | %.3f |\n", sum, r.update);
  }

  // GPU/CPU ratios where both ran.
  bool header = false;
  for (const Row& g : rows) {
    if (g.backend == "cpu" || !g.ok) continue;
    for (const Row& c : rows) {
      if (c.backend != "cpu" || c.K != g.K || !c.ok) continue;
      if (!header) {
        std::printf("\nspeed-up CPU/GPU (same run):\n| K | association | removal | addition | predict | update | total |\n"
                    "|---|---|---|---|---|---|---|\n");
        header = true;
      }
      auto q = [](double a, double b) { return b > 0 ? a / b : 0.0; };
      std::printf("| %d | %.1fx | %.1fx | %.1fx | %.1fx | %.1fx | %.1fx |\n", g.K, q(c.assoc, g.assoc),
                  q(c.removal, g.removal), q(c.addition, g.addition), q(c.predict, g.predict), q(c.update, g.update),
                  q(c.total, g.total));
    }
  }

  if (!rank.empty()) {
    std::printf("\nC <- C - A A^T alone (n = 12 + 3K, rank 3L = %d, random A and C, padded leading dimension as in the "
                "backend unless named, median of %d interleaved repetitions; "
                "flops = n^2 3L; bytes = lower triangle read + written + A; floor = max(flops / GEMM ceiling, bytes / "
                "copy ceiling)), and update step 3 A = P L^-T of the same shape (TRSM vs trtri + GEMM):\n"
                "| K | SYRK ms | panel-GEMM ms | recursive ms | recursive, ld = n, ms | recursive, C = 0, ms | floor ms "
                "| best / floor | best TFLOP/s | TRSM ms | trtri+GEMM ms |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
                3 * o.visible, o.rank_reps);
    for (const auto& kv : rank) {
      const RankUpdateTiming& t = kv.second;
      const double floor_ms =
          std::max(t.flops / (ceil.gemm_tflops * 1e12), t.bytes / (ceil.copy_gbps * 1e9)) * 1e3;
      const double best = std::min({t.syrk_ms, t.gemm_ms, t.recursive_ms});
      std::printf("| %d | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.2f | %.1f | %.3f | %.3f |\n", kv.first, t.syrk_ms,
                  t.gemm_ms, t.recursive_ms, t.recursive_unpadded_ms, t.recursive_zero_c_ms, floor_ms, best / floor_ms,
                  t.flops / (best * 1e-3) / 1e12, t.trsm_ms, t.inverse_ms);
    }
  }
  return 0;
}
