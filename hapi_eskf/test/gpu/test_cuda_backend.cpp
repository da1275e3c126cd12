// CUDA backend against the Eigen reference (CPU vs GPU: same inputs -> states
// equal to 1e-9 relative (FP64) over 100 iterations with additions and
// removals), method by method, bad-input parity, and the FP32 stability check. Every case skips without a CUDA device.
#include "backend_pair.hpp"

#include "hapi_eskf/backend/removal_plan.hpp"
#include "hapi_eskf/eskf/frame_error_block.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <cstdlib>
#include <limits>

namespace hapi_eskf {
namespace gputest {
namespace {

constexpr double kTol = 1e-9;  // FP64 parity

TEST(CudaBackend, FactoryReportsDeviceOrReason) {
  std::string why;
  const bool ok = cuda::deviceAvailable(0, &why);
  EXPECT_FALSE(why.empty());
  if (hapi_test::gpuRequired()) EXPECT_TRUE(ok) << "HAPI_REQUIRE_GPU=1: " << why;
  std::string err;
  auto b = cuda::makeCudaBackend(10, 32, kCameraMotionDim, cudaSettings(), &err);
  EXPECT_EQ(ok, b != nullptr) << err;
  if (!ok) EXPECT_FALSE(err.empty());
  EXPECT_EQ(cuda::makeCudaBackend(-1, 32, kCameraMotionDim, cudaSettings(), &err), nullptr);
  EXPECT_EQ(cuda::makeCudaBackend(10, 32, 13, cudaSettings(), &err), nullptr);  // no kernel for that pose block
  EskfSettings absent = cudaSettings();
  absent.cuda_device = 999;
  EXPECT_EQ(cuda::makeCudaBackend(10, 32, kCameraMotionDim, absent, &err), nullptr);
  EXPECT_FALSE(err.empty());
}

// Every method, with the pose block of each motion model (types.hpp).
class CudaBackendPoseBlock : public testing::TestWithParam<int> {};

TEST_P(CudaBackendPoseBlock, EachMethodMatchesCpu) {
  HAPI_REQUIRE_CUDA_DEVICE();
  const int P = GetParam();
  Rng r(1);
  BackendPair p(60, 32, cudaSettings(), P);
  ASSERT_TRUE(p.gpu);
  EXPECT_EQ(p.gpu->capacity(), 60);
  EXPECT_EQ(p.gpu->poseDim(), P);
  EXPECT_EQ(p.gpu->descriptorLength(), 32);
  EXPECT_GE(p.gpu->memoryBytes(), sizeof(double) * std::size_t(stateDim(60, P)) * stateDim(60, P));

  const PoseMat C0 = r.spd(P, 0.01);
  ASSERT_EQ(p.cpu->reset(C0), Status::kOk);
  ASSERT_EQ(p.gpu->reset(C0), Status::kOk);
  p.expectStatesEqual(0.0, "reset");  // a copy: bit-exact

  p.addRandom(r, 25);  // one call, several new landmarks (new-new blocks)
  p.expectStatesEqual(kTol, "add 25");
  p.addRandom(r, 1);
  p.expectStatesEqual(kTol, "add 1");

  const PoseMat F = randomF(r, P), Q = r.spd(P, 1e-4);
  ASSERT_EQ(p.cpu->predict(F, Q), Status::kOk);
  ASSERT_EQ(p.gpu->predict(F, Q), Status::kOk);
  p.expectStatesEqual(kTol, "predict");

  const std::vector<int> ms = {3, 0, 25, 3, 17};  // repeats allowed
  std::vector<Mat9> mc, mg;
  ASSERT_EQ(p.cpu->marginals(ms, &mc), Status::kOk);
  ASSERT_EQ(p.gpu->marginals(ms, &mg), Status::kOk);
  ASSERT_EQ(mc.size(), mg.size());
  for (std::size_t i = 0; i < mc.size(); ++i) EXPECT_LE(relDiff(mg[i], mc[i]), kTol) << i;

  const auto lc = p.cpu->landmarkCovariances(), lg = p.gpu->landmarkCovariances();
  ASSERT_EQ(lc.size(), lg.size());
  for (std::size_t i = 0; i < lc.size(); ++i) EXPECT_LE(relDiff(lg[i], lc[i]), kTol) << i;

  std::vector<MeasurementBlock> blocks;
  for (int s : r.distinct(26, 12)) blocks.push_back(randomBlock(r, s, 0.01));
  Eigen::VectorXd dxc, dxg;
  double nisc = 0, nisg = 0;
  ASSERT_EQ(p.cpu->update(blocks, &dxc, &nisc), Status::kOk);
  ASSERT_EQ(p.gpu->update(blocks, &dxg, &nisg), Status::kOk);
  EXPECT_LE(relDiff(dxg, dxc), kTol);
  EXPECT_NEAR(nisg, nisc, kTol * nisc);
  p.expectStatesEqual(kTol, "update");

  // Removal: scattered slots, including slot 0 and the last slot.
  ASSERT_EQ(p.cpu->removeLandmarks({0, 7, 8, 25}), Status::kOk);
  ASSERT_EQ(p.gpu->removeLandmarks({0, 7, 8, 25}), Status::kOk);
  p.expectStatesEqual(kTol, "remove scattered");
  // Removing only the tail slot moves nothing.
  ASSERT_EQ(p.cpu->removeLandmarks({21}), Status::kOk);
  ASSERT_EQ(p.gpu->removeLandmarks({21}), Status::kOk);
  p.expectStatesEqual(kTol, "remove tail");

  // Matching: queries are perturbed pool descriptors plus random ones.
  const auto pool = p.cpu->descriptors();
  std::vector<uint8_t> q = r.bytes(32 * 10);
  for (int i = 0; i < 5; ++i)
    for (int b = 0; b < 32; ++b) q[32 * i + b] = pool[32 * (3 * i) + b] ^ (b == i ? 1 : 0);
  std::vector<DescriptorMatch> oc, og;
  ASSERT_EQ(p.cpu->matchDescriptors(q.data(), 10, &oc), Status::kOk);
  ASSERT_EQ(p.gpu->matchDescriptors(q.data(), 10, &og), Status::kOk);
  ASSERT_EQ(oc.size(), og.size());
  for (std::size_t i = 0; i < oc.size(); ++i) {
    EXPECT_EQ(og[i].best_slot, oc[i].best_slot) << i;
    EXPECT_EQ(og[i].best_distance, oc[i].best_distance) << i;
    EXPECT_EQ(og[i].second_slot, oc[i].second_slot) << i;
    EXPECT_EQ(og[i].second_distance, oc[i].second_distance) << i;
  }
  EXPECT_EQ(og[2].best_slot, 6);
  EXPECT_EQ(og[2].best_distance, 1);
}

// The pose blocks of the motion models, and the inertial one with the frame-error rows.
INSTANTIATE_TEST_SUITE_P(MotionModels, CudaBackendPoseBlock,
                         testing::Values(kCameraMotionDim, kInertialDim, kInertialDim + kFrameErrorDim));

TEST(CudaBackend, HammingTiesGoToTheLowestSlotLikeCpu) {
  HAPI_REQUIRE_CUDA_DEVICE();
  Rng r(2);
  for (int dlen : {32, 7}) {  // word path and byte path of the kernel
    BackendPair p(700, dlen);
    ASSERT_TRUE(p.gpu);
    ASSERT_EQ(p.cpu->reset(r.spd12(0.01)), Status::kOk);
    ASSERT_EQ(p.gpu->reset(r.spd12(0.01)), Status::kOk);
    // Few distinct descriptors, many copies: every query has exact ties.
    std::vector<std::vector<uint8_t>> proto(4);
    for (auto& d : proto) d = r.bytes(dlen);
    std::vector<std::vector<uint8_t>> store(650);
    std::vector<NewLandmarkBlock> blocks;
    for (int k = 0; k < 650; ++k) {
      store[k] = proto[r.i(0, 3)];
      blocks.push_back(randomNewBlock(r, store[k]));
    }
    ASSERT_EQ(p.cpu->addLandmarks(blocks), Status::kOk);
    ASSERT_EQ(p.gpu->addLandmarks(blocks), Status::kOk);
    std::vector<uint8_t> q;
    for (auto& d : proto) q.insert(q.end(), d.begin(), d.end());
    const auto extra = r.bytes(dlen * 20);
    q.insert(q.end(), extra.begin(), extra.end());
    const int nq = static_cast<int>(q.size()) / dlen;
    std::vector<DescriptorMatch> oc, og;
    ASSERT_EQ(p.cpu->matchDescriptors(q.data(), nq, &oc), Status::kOk);
    ASSERT_EQ(p.gpu->matchDescriptors(q.data(), nq, &og), Status::kOk);
    for (int i = 0; i < nq; ++i) {
      EXPECT_EQ(og[i].best_slot, oc[i].best_slot) << dlen << " q" << i;
      EXPECT_EQ(og[i].best_distance, oc[i].best_distance) << dlen << " q" << i;
      EXPECT_EQ(og[i].second_slot, oc[i].second_slot) << dlen << " q" << i;
      EXPECT_EQ(og[i].second_distance, oc[i].second_distance) << dlen << " q" << i;
    }
  }
}

TEST(CudaBackend, EmptyPoolAndNoQueriesLikeCpu) {
  HAPI_REQUIRE_CUDA_DEVICE();
  BackendPair p(5, 32);
  ASSERT_TRUE(p.gpu);
  const std::vector<uint8_t> q(64, 0xAB);
  std::vector<DescriptorMatch> og;
  ASSERT_EQ(p.gpu->matchDescriptors(q.data(), 2, &og), Status::kOk);
  ASSERT_EQ(og.size(), 2u);
  EXPECT_EQ(og[0].best_slot, -1);
  EXPECT_EQ(og[0].second_slot, -1);
  ASSERT_EQ(p.gpu->matchDescriptors(nullptr, 0, &og), Status::kOk);
  EXPECT_TRUE(og.empty());
}

// The backend parity requirement (docs/DESIGN.md "Parity tests"): 100 iterations of predict / match / update /
// remove / add with every state compared after every iteration, for each
// schedule of the rank update and each way of forming A = P L^-T
// (EskfSettings::cuda_rank_update, cuda_solve). The pool stays below the
// recursive schedule's 512-row leaf here; LargePoolRemovalAndGatherMatchCpu
// runs its recursion several levels deep. kAuto leaves the choice to the
// backend.
void runHundredIterations(CudaRankUpdate rank_update, CudaSolve solve) {
  Rng r(3);
  BackendPair p(170, 32, cudaSettings(Precision::kFp64, rank_update, solve));
  ASSERT_TRUE(p.gpu);
  const Mat12 C0 = r.spd12(0.01);
  ASSERT_EQ(p.cpu->reset(C0), Status::kOk);
  ASSERT_EQ(p.gpu->reset(C0), Status::kOk);
  p.addRandom(r, 40);
  int removed_total = 0;
  for (int it = 0; it < 100; ++it) {
    const Mat12 F = randomF(r), Q = r.spd12(1e-4);
    ASSERT_EQ(p.cpu->predict(F, Q), Status::kOk);
    ASSERT_EQ(p.gpu->predict(F, Q), Status::kOk);

    const int K = p.cpu->numLandmarks();
    std::vector<MeasurementBlock> blocks;
    for (int s : r.distinct(K, r.i(1, std::min(K, 50)))) blocks.push_back(randomBlock(r, s, 0.01));
    Eigen::VectorXd dxc, dxg;
    double nisc = 0, nisg = 0;
    ASSERT_EQ(p.cpu->update(blocks, &dxc, &nisc), Status::kOk) << it;
    ASSERT_EQ(p.gpu->update(blocks, &dxg, &nisg), Status::kOk) << it;
    EXPECT_LE(relDiff(dxg, dxc), kTol) << it;
    EXPECT_NEAR(nisg, nisc, kTol * std::max(1.0, nisc)) << it;

    // Removal: sometimes slot 0 (everything moves), sometimes scattered.
    std::vector<int> rem = r.distinct(K, r.i(0, std::min(K, 25)));
    if (it % 7 == 0 && std::find(rem.begin(), rem.end(), 0) == rem.end()) rem.push_back(0);
    ASSERT_EQ(p.cpu->removeLandmarks(rem), Status::kOk) << it;
    ASSERT_EQ(p.gpu->removeLandmarks(rem), Status::kOk) << it;
    removed_total += static_cast<int>(rem.size());

    const int room = p.cpu->capacity() - p.cpu->numLandmarks();
    p.addRandom(r, std::min(room, r.i(0, 30)));

    std::vector<uint8_t> q = r.bytes(32 * 8);
    std::vector<DescriptorMatch> oc, og;
    ASSERT_EQ(p.cpu->matchDescriptors(q.data(), 8, &oc), Status::kOk);
    ASSERT_EQ(p.gpu->matchDescriptors(q.data(), 8, &og), Status::kOk);
    for (int i = 0; i < 8; ++i) {
      EXPECT_EQ(og[i].best_slot, oc[i].best_slot);
      EXPECT_EQ(og[i].second_slot, oc[i].second_slot);
      EXPECT_EQ(og[i].best_distance, oc[i].best_distance);
    }
    p.expectStatesEqual(kTol, ("iteration " + std::to_string(it)).c_str());
    if (::testing::Test::HasFailure()) return;
  }
  EXPECT_GT(removed_total, 500);
  // Still a covariance: symmetric positive semi-definite.
  const Eigen::MatrixXd C = p.gpu->denseCovariance();
  const double lmin = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(C).eigenvalues().minCoeff();
  EXPECT_GT(lmin, -1e-10 * C.cwiseAbs().maxCoeff());
}

TEST(CudaBackend, HundredIterationsMatchCpuAutomaticChoice) {  // the default: by size
  HAPI_REQUIRE_CUDA_DEVICE();
  runHundredIterations(CudaRankUpdate::kAuto, CudaSolve::kAuto);
}

TEST(CudaBackend, HundredIterationsMatchCpuRecursiveInverse) {
  HAPI_REQUIRE_CUDA_DEVICE();
  runHundredIterations(CudaRankUpdate::kRecursive, CudaSolve::kInverse);
}

TEST(CudaBackend, HundredIterationsMatchCpuPanelGemmInverse) {
  HAPI_REQUIRE_CUDA_DEVICE();
  runHundredIterations(CudaRankUpdate::kPanelGemm, CudaSolve::kInverse);
}

TEST(CudaBackend, HundredIterationsMatchCpuSyrkTrsm) {
  HAPI_REQUIRE_CUDA_DEVICE();
  runHundredIterations(CudaRankUpdate::kSyrk, CudaSolve::kTrsm);
}

TEST(CudaBackend, HundredIterationsMatchCpuRecursiveTrsm) {
  HAPI_REQUIRE_CUDA_DEVICE();
  runHundredIterations(CudaRankUpdate::kRecursive, CudaSolve::kTrsm);
}

// A pool large enough that the removal moves hundreds of landmarks across
// many thread blocks (n = 4212), the update's gather runs over many 32 x 32
// tiles (m > 32) and the recursive rank update (selected here: by size the
// backend would take SYRK) goes several levels deep, with A from trtri + GEMM.
// Each removal is also checked bit-exactly against the GPU's own state before
// it (the refill is a pure copy), independently of the CPU reference.
TEST(CudaBackend, LargePoolRemovalAndGatherMatchCpu) {
  HAPI_REQUIRE_CUDA_DEVICE();
  Rng r(6);
  BackendPair p(1500, 32, cudaSettings(Precision::kFp64, CudaRankUpdate::kRecursive, CudaSolve::kInverse));
  ASSERT_TRUE(p.gpu);
  const Mat12 C0 = r.spd12(0.01);
  ASSERT_EQ(p.cpu->reset(C0), Status::kOk);
  ASSERT_EQ(p.gpu->reset(C0), Status::kOk);
  p.addRandom(r, 1400);
  p.expectStatesEqual(kTol, "add 1400");

  auto removeBoth = [&](std::vector<int> rem, const char* what) {
    const Eigen::MatrixXd before = p.gpu->denseCovariance();
    const int K = p.gpu->numLandmarks();
    std::vector<int> idx;
    for (int i = 0; i < kCameraMotionDim; ++i) idx.push_back(i);
    for (int k : oldSlotOfNew(K, rem))
      for (int c = 0; c < 3; ++c) idx.push_back(landmarkRow(k, kCameraMotionDim) + c);
    Eigen::MatrixXd expect(idx.size(), idx.size());
    for (std::size_t c = 0; c < idx.size(); ++c)
      for (std::size_t i = 0; i < idx.size(); ++i) expect(i, c) = before(idx[i], idx[c]);
    ASSERT_EQ(p.cpu->removeLandmarks(rem), Status::kOk) << what;
    ASSERT_EQ(p.gpu->removeLandmarks(rem), Status::kOk) << what;
    EXPECT_TRUE(p.gpu->denseCovariance() == expect) << what << ": the refill is not an exact copy";
    p.expectStatesEqual(kTol, what);
  };

  for (int round = 0; round < 3; ++round) {
    const int K = p.cpu->numLandmarks();
    std::vector<MeasurementBlock> blocks;
    for (int s : r.distinct(K, 70)) blocks.push_back(randomBlock(r, s, 0.01));
    Eigen::VectorXd dxc, dxg;
    ASSERT_EQ(p.cpu->update(blocks, &dxc), Status::kOk) << round;
    ASSERT_EQ(p.gpu->update(blocks, &dxg), Status::kOk) << round;
    EXPECT_LE(relDiff(dxg, dxc), kTol) << round;
    p.expectStatesEqual(kTol, "large update");

    std::vector<int> rem = r.distinct(K, 70);  // scattered, shifts up to 210 columns
    if (round == 1) rem.push_back(K - 1);  // with the last slot (may already be in: deduplicated)
    std::sort(rem.begin(), rem.end());
    rem.erase(std::unique(rem.begin(), rem.end()), rem.end());
    removeBoth(rem, "scattered");
    removeBoth({p.cpu->numLandmarks() / 2}, "one middle slot");  // the last landmark moves there
    removeBoth({0, 1, 2, 3, 4, 5, 6, 7}, "leading run");         // the last 8 move to the front
    p.addRandom(r, 60);
  }
}

// Same Status for the same bad input, and neither state changes.
TEST(CudaBackend, BadInputParity) {
  HAPI_REQUIRE_CUDA_DEVICE();
  Rng r(4);
  const int dlen = 8;
  BackendPair p(8, dlen);
  ASSERT_TRUE(p.gpu);
  const Mat12 C0 = r.spd12(0.01);
  ASSERT_EQ(p.cpu->reset(C0), Status::kOk);
  ASSERT_EQ(p.gpu->reset(C0), Status::kOk);
  std::vector<std::vector<uint8_t>> store;
  p.addRandom(r, 5, &store);
  const Snapshot sc(*p.cpu), sg(*p.gpu);
  const std::vector<uint8_t> d = r.bytes(dlen);

  auto both = [&](const char* what, auto&& call) {
    Eigen::VectorXd dxc = Eigen::VectorXd::Constant(3, 7.0), dxg = dxc;
    const Status a = call(*p.cpu, &dxc);
    const Status b = call(*p.gpu, &dxg);
    EXPECT_EQ(a, b) << what << ": cpu " << toString(a) << " gpu " << toString(b);
    EXPECT_NE(b, Status::kOk) << what;
    EXPECT_TRUE((dxg.array() == 7.0).all()) << what;
    EXPECT_TRUE(sc.same(*p.cpu)) << what;
    EXPECT_TRUE(sg.same(*p.gpu)) << what;
  };
  using B = CovarianceBackend;
  using V = Eigen::VectorXd;
  both("empty update", [&](B& b, V* dx) { return b.update({}, dx); });
  both("null dx", [&](B& b, V*) { return b.update({randomBlock(r, 0, 0.01)}, nullptr); });
  {
    auto nan_block = randomBlock(r, 1, 0.01);
    nan_block.innovation.x() = std::nan("");
    const auto ok0 = randomBlock(r, 0, 0.01);
    both("NaN innovation", [&](B& b, V* dx) { return b.update({ok0, nan_block}, dx); });
    auto inf_h = randomBlock(r, 1, 0.01);
    inf_h.H_pose(2, 4) = std::numeric_limits<double>::infinity();
    both("Inf H", [&](B& b, V* dx) { return b.update({inf_h}, dx); });
  }
  {
    const auto a = randomBlock(r, 2, 0.01), c = randomBlock(r, 2, 0.01);
    both("duplicate slot", [&](B& b, V* dx) { return b.update({a, c}, dx); });
    const auto out = randomBlock(r, 5, 0.01), neg = randomBlock(r, -1, 0.01);
    both("slot >= K", [&](B& b, V* dx) { return b.update({out}, dx); });
    both("slot < 0", [&](B& b, V* dx) { return b.update({neg}, dx); });
  }
  {
    std::vector<MeasurementBlock> many;
    for (int s = 0; s < 6; ++s) many.push_back(randomBlock(r, s % 5, 0.01));
    both("more measurements than landmarks", [&](B& b, V* dx) { return b.update(many, dx); });
  }
  {
    const auto ok0 = randomBlock(r, 0, 0.01);
    auto neg = randomBlock(r, 3, 0.01);
    neg.R = -100.0 * Mat3::Identity();
    both("non-PD S", [&](B& b, V* dx) { return b.update({ok0, neg}, dx); });
  }
  {
    auto bad = randomNewBlock(r, d);
    bad.Cz(0, 0) = std::nan("");
    both("NaN Cz", [&](B& b, V*) { return b.addLandmarks({bad}); });
    const auto ok = randomNewBlock(r, d);
    auto notpd = randomNewBlock(r, d);
    notpd.Cz = -Mat3::Identity();
    both("non-PD Cz", [&](B& b, V*) { return b.addLandmarks({ok, notpd}); });
    auto nodesc = randomNewBlock(r, d);
    nodesc.descriptor = nullptr;
    both("null descriptor", [&](B& b, V*) { return b.addLandmarks({nodesc}); });
    const std::vector<NewLandmarkBlock> too_many(4, randomNewBlock(r, d));
    both("over capacity", [&](B& b, V*) { return b.addLandmarks(too_many); });
  }
  both("duplicate removal", [&](B& b, V*) { return b.removeLandmarks({1, 1}); });
  both("removal out of range", [&](B& b, V*) { return b.removeLandmarks({0, 5}); });
  {
    Mat12 F = Mat12::Identity();
    F(1, 2) = std::nan("");
    both("NaN F", [&](B& b, V*) { return b.predict(F, Mat12::Zero()); });
    Mat12 notpd = Mat12::Identity();
    notpd(4, 4) = -1;
    both("non-PD reset", [&](B& b, V*) { return b.reset(notpd); });
    Mat12 asym = Mat12::Identity();
    asym(0, 1) = 0.5;
    both("asymmetric reset", [&](B& b, V*) { return b.reset(asym); });
  }
  both("marginal out of range", [&](B& b, V*) {
    std::vector<Mat9> M;
    return b.marginals({0, 9}, &M);
  });
  both("match null out", [&](B& b, V*) { return b.matchDescriptors(d.data(), 1, nullptr); });
  both("match null queries", [&](B& b, V*) {
    std::vector<DescriptorMatch> o;
    return b.matchDescriptors(nullptr, 2, &o);
  });
}

// FP32 storage (settings.hpp Precision::kFp32): C in float on the device. The
// filter must stay usable over a long run: every update accepted, C symmetric
// PSD within float round-off, and the state within float-level error of FP64.
TEST(CudaBackend, Fp32StaysStableAndCloseToFp64) {
  HAPI_REQUIRE_CUDA_DEVICE();
  Rng r(5);
  BackendPair p(120, 32, cudaSettings(Precision::kFp32));
  ASSERT_TRUE(p.gpu);
  EXPECT_STREQ(p.gpu->name(), "cuda-fp32");
  const Mat12 C0 = r.spd12(0.01);
  ASSERT_EQ(p.cpu->reset(C0), Status::kOk);
  ASSERT_EQ(p.gpu->reset(C0), Status::kOk);
  p.addRandom(r, 60);
  double worst_dx = 0, worst_pose = 0;
  for (int it = 0; it < 200; ++it) {
    Mat12 F = Mat12::Identity();
    F.block<3, 3>(0, 6) = 0.05 * Mat3::Identity();  // constant-velocity coupling
    F.block<3, 3>(3, 9) = 0.05 * Mat3::Identity();
    const Mat12 Q = 1e-5 * Mat12::Identity();
    ASSERT_EQ(p.cpu->predict(F, Q), Status::kOk);
    ASSERT_EQ(p.gpu->predict(F, Q), Status::kOk);
    const int K = p.cpu->numLandmarks();
    std::vector<MeasurementBlock> blocks;
    for (int s : r.distinct(K, 40)) blocks.push_back(randomBlock(r, s, 1e-4));
    Eigen::VectorXd dxc, dxg;
    ASSERT_EQ(p.cpu->update(blocks, &dxc), Status::kOk) << it;
    ASSERT_EQ(p.gpu->update(blocks, &dxg), Status::kOk) << it;
    worst_dx = std::max(worst_dx, relDiff(dxg, dxc));
    worst_pose = std::max(worst_pose, relDiff(p.gpu->poseCovariance(), p.cpu->poseCovariance()));
    const std::vector<int> rem = r.distinct(K, 10);
    ASSERT_EQ(p.cpu->removeLandmarks(rem), Status::kOk);
    ASSERT_EQ(p.gpu->removeLandmarks(rem), Status::kOk);
    p.addRandom(r, 10);
  }
  EXPECT_LT(worst_dx, 1e-2);
  EXPECT_LT(worst_pose, 1e-2);
  const Eigen::MatrixXd Cg = p.gpu->denseCovariance();
  const double lmin = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Cg).eigenvalues().minCoeff();
  EXPECT_GT(lmin, -1e-5 * Cg.cwiseAbs().maxCoeff());
  RecordProperty("fp32_worst_dx_rel", std::to_string(worst_dx));
  RecordProperty("fp32_worst_pose_cov_rel", std::to_string(worst_pose));
  std::printf("FP32 vs FP64 over 200 iterations: worst dx rel %.3g, worst pose-covariance rel %.3g, min eig %.3g\n",
              worst_dx, worst_pose, lmin);
}

}  // namespace
}  // namespace gputest
}  // namespace hapi_eskf
