// hapi_eskf_bench: per-stage timings of the filter core for a list of
// pool sizes K, CPU reference and CUDA backend in the same run, with the
// device's measured ceilings and the floor of the C <- C - A A^T step.
//   hapi_eskf_bench [--k 1000,2000,...] [--iters 50] [--cpu-iters 3]
//                   [--backend cpu|cuda|both] [--precision fp64|fp32]
//                   [--cpu-max-k 2000] [--visible 200] [--fresh 20] [--rank-reps 3 (0: none)]
//                   [--cuda-rank-update auto|syrk|gemm|recursive]
//                   [--cuda-solve auto|trsm|inverse] [--cuda-stage-times]
//                   [--cpu-la blas,eigen] [--covariance-update dense,partitioned]
//                   [--partition-max-active N] [--partition-flush-shares 1,4,...]
//                   [--partition-flush-background 0,1]
//                   [--scenario random|sweep] [--sweep-step N]
//                   [--frame-period-ms T] [--no-cpu-rates]
// CPU rows: one per --cpu-la x --covariance-update pair (cpu-blas,
// cpu-eigen, cpu-blas-partitioned, ...), CUDA rows one per --covariance-update
// (cuda-fp64, cuda-fp64-partitioned), a partitioned row per
// --partition-flush-shares value (named "... shares N" when N > 1) and
// --partition-flush-background value (named "... background" when 1), side by
// side in the same run, with
// this machine's DGEMM/DSYRK rates measured first (cpu_ceilings.hpp).
// --scenario: which landmarks a frame re-observes (scenario.hpp Visibility):
// random (the visible set jumps every frame, the default) or sweep.
// --frame-period-ms: frames start at this period, as from a camera (a frame
// that ends late starts the next one at once); 0 (the default) runs them back
// to back. Work a backend defers past a frame (background shares) runs in
// the time between frames and is only seen in a frame's time when it is not
// done by the next frame's start.
// The --precision and --cuda-* flags set the EskfSettings fields of the same
// names (settings.hpp) for the CUDA backend (device 0, where the
// ceilings are measured). Builds and runs without a GPU (CPU rows only).
#include "cpu_ceilings.hpp"
#include "device_ceilings.hpp"
#include "scenario.hpp"

#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "../src/covariance/cpu_linear_algebra.hpp"
#include "hapi_nodelet_kit/sample_quantiles.hpp"
#ifdef HAPI_ESKF_BENCH_WITH_CUDA
#include "hapi_eskf/covariance/cuda_backend.hpp"
#include "../src/covariance/cuda/stage_times.hpp"
#endif

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <chrono>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <tuple>
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
  std::vector<CpuLinearAlgebra> cpu_la = {CpuLinearAlgebra::kBlas, CpuLinearAlgebra::kEigen};
  std::vector<CovarianceUpdate> cov_update = {CovarianceUpdate::kDense};
  int partition_max_active = EskfSettings().partition_max_active;
  std::vector<int> partition_flush_shares = {EskfSettings().partition_flush_shares};
  std::vector<int> partition_flush_background = {EskfSettings().partition_flush_background ? 1 : 0};
  int frame_period_ms = 0;
  Visibility visibility = Visibility::kRandom;
  int sweep_step = 10;
  bool cpu_rates = true;
};

template <typename E>
std::vector<E> parseList(const std::string& text, const char* flag);

[[noreturn]] void usage(const char* msg) {
  std::fprintf(stderr,
               "error: %s\nusage: hapi_eskf_bench [--k 1000,2000] [--iters N] [--cpu-iters N] [--backend cpu|cuda|both]\n"
               "       [--precision fp64|fp32] [--cpu-max-k K] [--visible L] [--fresh M] [--rank-reps N]\n"
               "       [--cuda-rank-update auto|syrk|gemm|recursive] [--cuda-solve auto|trsm|inverse] [--cuda-stage-times]\n"
               "       [--cpu-la blas,eigen] [--covariance-update dense,partitioned] [--partition-max-active N]\n"
               "       [--partition-flush-shares 1,4] [--partition-flush-background 0,1] [--scenario random|sweep]\n"
               "       [--sweep-step N] [--frame-period-ms T] [--no-cpu-rates]\n",
               msg);
  std::exit(2);
}

int toInt(const char* s, const char* flag) {
  char* end = nullptr;
  const long v = std::strtol(s, &end, 10);
  if (end == s || *end != '\0' || v < 0 || v > 10000000) usage((std::string("bad value for ") + flag).c_str());
  return static_cast<int>(v);
}

std::vector<int> intList(const char* text, const char* flag) {
  std::vector<int> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(toInt(item.c_str(), flag));
  if (out.empty()) usage((std::string(flag) + " needs at least one value").c_str());
  return out;
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
      o.ks = intList(next(), "--k");
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
    } else if (a == "--cpu-la") {
      o.cpu_la = parseList<CpuLinearAlgebra>(next(), "--cpu-la");
    } else if (a == "--covariance-update") {
      o.cov_update = parseList<CovarianceUpdate>(next(), "--covariance-update");
    } else if (a == "--partition-max-active") {
      o.partition_max_active = toInt(next(), "--partition-max-active");
    } else if (a == "--partition-flush-shares") {
      o.partition_flush_shares = intList(next(), "--partition-flush-shares");
    } else if (a == "--partition-flush-background") {
      o.partition_flush_background = intList(next(), "--partition-flush-background");
      for (int v : o.partition_flush_background)
        if (v > 1) usage("--partition-flush-background takes 0 and/or 1");
    } else if (a == "--frame-period-ms") {
      o.frame_period_ms = toInt(next(), "--frame-period-ms");
    } else if (a == "--scenario") {
      const std::string v = next();
      if (v == "random") o.visibility = Visibility::kRandom;
      else if (v == "sweep") o.visibility = Visibility::kSweep;
      else usage("--scenario must be random or sweep");
    } else if (a == "--sweep-step") {
      o.sweep_step = toInt(next(), "--sweep-step");
    } else if (a == "--no-cpu-rates") {
      o.cpu_rates = false;
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

template <typename E>
std::vector<E> parseList(const std::string& text, const char* flag) {
  std::vector<E> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    E e;
    if (!parseValue(item, &e)) usage((std::string("bad value for ") + flag + ": " + item).c_str());
    out.push_back(e);
  }
  if (out.empty()) usage((std::string(flag) + " needs at least one value").c_str());
  return out;
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
  double total_p99 = 0, total_max = 0, total_mean = 0;  // mean: the amortised cost
  int flushes = 0;         // partitioned: flushes in the measured iterations
  double flush_ms = 0;     // their mean time
  double flush_max_ms = 0; // the largest flush time of one iteration
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
  Scenario sc(std::move(b), K, o.visible, o.fresh, 1234u + K, o.visibility, o.sweep_step);
  if (!sc.fill()) {
    r.note = "filling the pool failed: " + sc.backend().lastError();
    return r;
  }
  r.note.clear();
  std::vector<double> a, rm, ad, pr, up, to, bk, nu, mv, fl;
  bool ok = true;
  std::vector<std::vector<double>> stage_samples(kStageCount);
  const auto period = std::chrono::milliseconds(o.frame_period_ms);
  auto frame_start = std::chrono::steady_clock::now();
  for (int i = 0; i < warmup + iters; ++i) {
    if (o.frame_period_ms > 0) {  // the camera's next frame; a late frame starts the next one at once
      std::this_thread::sleep_until(frame_start);
      frame_start = std::max(frame_start + period, std::chrono::steady_clock::now());
    }
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
    r.flushes += t.flushes;
    if (t.flushes > 0) fl.push_back(t.flush_ms / t.flushes);
    r.flush_max_ms = std::max(r.flush_max_ms, t.flush_ms);
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
  r.total_p99 = hapi_nodelet_kit::quantileRoundedPosition(to, 0.99, 0.0);
  r.total_max = to.empty() ? 0.0 : *std::max_element(to.begin(), to.end());
  for (double v : to) r.total_mean += v / to.size();
  double fsum = 0;
  for (double f : fl) fsum += f;
  r.flush_ms = fl.empty() ? 0.0 : fsum / fl.size();
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
              "total = predict + association + update + removal + addition + frameCompleted\n",
              o.warmup, o.cpu_warmup);
  if (o.frame_period_ms > 0)
    std::printf("frames start every %d ms (a late frame starts the next at once)\n", o.frame_period_ms);
  else
    std::printf("frames run back to back\n");
  if (o.visibility == Visibility::kSweep)
    std::printf("scenario: sweep, the view advances %d landmarks per frame (%d of %d visible change per frame)\n",
                o.sweep_step, o.sweep_step, o.visible);
  else
    std::printf("scenario: random, the visible set jumps every frame\n");
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

  std::map<int, std::map<std::string, CpuRates>> cpu_rates;  // K -> la -> rates at the update's shape
  if (o.cpu && o.cpu_rates) {
    std::printf("CPU linear algebra of this machine (same run; OpenBLAS %s):\n",
                cpu_la::blasCompiledIn() ? "compiled in" : "NOT compiled in, blas = eigen");
    for (CpuLinearAlgebra la : o.cpu_la)
      std::printf("  %s DGEMM 1536^3: %.1f GFLOP/s\n", valueText(la).c_str(), measureCpuGemm(la, 1536, 2));
    for (int K : o.ks) {
      if (K > o.cpu_max_k) continue;
      const int n = stateDim(K, kCameraMotionDim), k = 3 * o.visible;
      for (CpuLinearAlgebra la : o.cpu_la) {
        const CpuRates cr = measureCpuUpdateShapes(la, n, k, 3);
        cpu_rates[K][valueText(la)] = cr;
        std::printf("  %s K=%d (n=%d, k=%d): DSYRK %.2f ms = %.1f GFLOP/s, DPOTRF+DTRSM %.2f ms = %.1f GFLOP/s\n",
                    valueText(la).c_str(), K, n, k, cr.syrk_ms, cr.syrk_gflops, cr.factor_ms, cr.factor_gflops);
      }
    }
  }

  std::vector<Row> rows;
  std::map<int, RankUpdateTiming> rank;
  // Rows per backend: (covariance update, flush shares, background): the
  // dense update once, the partitioned one per --partition-flush-shares x
  // --partition-flush-background value.
  std::vector<std::tuple<CovarianceUpdate, int, bool>> variants;
  for (CovarianceUpdate cu : o.cov_update)
    if (cu == CovarianceUpdate::kPartitioned)
      for (int shares : o.partition_flush_shares)
        for (int bg : o.partition_flush_background) variants.emplace_back(cu, shares, bg != 0);
    else
      variants.emplace_back(cu, 1, false);
  auto label = [](const std::string& name, int shares, bool bg) {
    return (shares > 1 ? name + " shares " + std::to_string(shares) : name) + (bg ? " background" : "");
  };
  for (int K : o.ks) {
    if (have_cuda) {
      const int n = stateDim(K, kCameraMotionDim);
      RankUpdateTiming rt;
      std::string w;
      if (o.rank_reps <= 0) {
        // --rank-reps 0: no isolated rank update (it needs a second n x n buffer)
      } else if (measureRankUpdate(fp32, n, 3 * o.visible, o.rank_reps, &rt, &w)) {
        rank[K] = rt;
      } else {
        std::printf("K=%d: isolated rank update not measured: %s\n", K, w.c_str());
      }
#ifdef HAPI_ESKF_BENCH_WITH_CUDA
      // One row per --covariance-update (the partitioned one FP64 only).
      for (const auto& [cu, shares, bg] : variants) {
        std::string err;
        EskfSettings s = o.backend;
        s.covariance_update = cu;
        s.partition_max_active = o.partition_max_active;
        s.partition_flush_shares = shares;
        s.partition_flush_background = bg;
        auto b = cu == CovarianceUpdate::kPartitioned
                     ? cuda::makePartitionedCudaBackend(K, Scenario::kDescLen, kCameraMotionDim, s, &err)
                     : cuda::makeCudaBackend(K, Scenario::kDescLen, kCameraMotionDim, s, &err);
        if (!b) {
          Row r;
          r.backend = label(std::string("cuda-") + toString(o.backend.precision) +
                                (cu == CovarianceUpdate::kPartitioned ? "-partitioned" : ""),
                            shares, bg);
          r.K = K;
          r.note = err;
          rows.push_back(r);
        } else {
          const std::string name = label(b->name(), shares, bg);  // before the move (argument order is unspecified)
          rows.push_back(run(name, std::move(b), K, o.iters, o.warmup, o));
        }
      }
#endif
    }
    if (o.cpu && K <= o.cpu_max_k)
      for (const auto& [cu, shares, bg] : variants)
        for (CpuLinearAlgebra la : o.cpu_la) {
          auto b = cu == CovarianceUpdate::kPartitioned
                       ? makePartitionedCpuBackend(K, Scenario::kDescLen, kCameraMotionDim, la, o.partition_max_active,
                                                   shares, bg)
                       : makeCpuBackend(K, Scenario::kDescLen, kCameraMotionDim, la);
          const std::string name = label(b->name(), shares, bg);
          rows.push_back(run(name, std::move(b), K, o.cpu_iters, o.cpu_warmup, o));
        }
    for (const Row& r : rows)
      if (r.K == K)
        std::printf("  K=%d %s: %s total %.3f ms\n", K, r.backend.c_str(), r.ok ? "ok" : r.note.c_str(), r.total);
  }

  std::printf("\n| backend | K | iters | association | removal | addition | predict | update | total | bookkeeping "
              "(rem+add) | memory GB | L used | moved per removal | total p99 | total max | total mean | flushes | ms per flush "
              "| flush max ms |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    if (!r.ok) {
      std::printf("| %s | %d | - | %s |\n", r.backend.c_str(), r.K, r.note.c_str());
      continue;
    }
    std::printf("| %s | %d | %d | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.2f | %d | %.0f | %.3f | %.3f | %.3f "
                "| %d | %.3f | %.3f |\n",
                r.backend.c_str(), r.K, r.iters, r.assoc, r.removal, r.addition, r.predict, r.update, r.total,
                r.bookkeeping, r.mem_gb, r.n_updated, r.moved, r.total_p99, r.total_max, r.total_mean, r.flushes,
                r.flush_ms, r.flush_max_ms);
  }

  // CPU variants side by side (same run): each against the first CPU row of
  // its K, and the dense rows' update rate against this machine's rates.
  bool cpu_header = false;
  for (const Row& r : rows) {
    if (r.backend.rfind("cpu", 0) != 0 || !r.ok) continue;
    const Row* first = nullptr;
    for (const Row& c : rows)
      if (c.K == r.K && c.ok && c.backend.rfind("cpu", 0) == 0) {
        first = &c;
        break;
      }
    if (!cpu_header) {
      std::printf("\nCPU variants (same run; ratio = this row / the first CPU row of its K; update rate = "
                  "(n^2 k + n k^2 + k^3/3) / update time, k = 3 x L used, vs DSYRK of that shape and DGEMM):\n"
                  "| backend | K | update ms | total ms | update ratio | total ratio | update GFLOP/s | DSYRK GFLOP/s "
                  "| DSYRK / update rate |\n|---|---|---|---|---|---|---|---|---|\n");
      cpu_header = true;
    }
    const int n = stateDim(r.K, kCameraMotionDim), k = 3 * r.n_updated;
    const double rate = r.update > 0 ? updateFlops(n, k) / (r.update * 1e-3) / 1e9 : 0.0;
    const std::string la = r.backend.find("eigen") != std::string::npos ? "eigen" : "blas";
    double syrk = 0;
    if (cpu_rates.count(r.K) && cpu_rates[r.K].count(la)) syrk = cpu_rates[r.K][la].syrk_gflops;
    if (r.backend.find("partitioned") != std::string::npos)  // fewer flops by design: no dense rate
      std::printf("| %s | %d | %.3f | %.3f | %.2f | %.2f | - | %.1f | - |\n", r.backend.c_str(), r.K, r.update, r.total,
                  r.update / first->update, r.total / first->total, syrk);
    else
      std::printf("| %s | %d | %.3f | %.3f | %.2f | %.2f | %.1f | %.1f | %.2f |\n", r.backend.c_str(), r.K, r.update,
                  r.total, r.update / first->update, r.total / first->total, rate, syrk, rate > 0 ? syrk / rate : 0.0);
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
    if (g.backend.rfind("cpu", 0) == 0 || !g.ok) continue;
    for (const Row& c : rows) {
      if (c.backend.rfind("cpu", 0) != 0 || c.K != g.K || !c.ok) continue;
      if (!header) {
        std::printf("\nspeed-up CPU/GPU (same run):\n| CPU row | K | association | removal | addition | predict | update | total |\n"
                    "|---|---|---|---|---|---|---|---|\n");
        header = true;
      }
      auto q = [](double a, double b) { return b > 0 ? a / b : 0.0; };
      std::printf("| %s | %d | %.1fx | %.1fx | %.1fx | %.1fx | %.1fx | %.1fx |\n", c.backend.c_str(), g.K, q(c.assoc, g.assoc),
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
