// Eigen backend against a dense textbook EKF and its bookkeeping invariants
// (storage contract of covariance_backend.hpp).
#include "hapi_eskf/backend/removal_plan.hpp"
#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "hapi_eskf/eskf/storage_factory.hpp"
#include "hapi_eskf/so3.hpp"
#include "test_random.hpp"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>

namespace hapi_eskf {
namespace {

using MatX = Eigen::MatrixXd;
using VecX = Eigen::VectorXd;

using testing_random::Rng;
using testing_random::randomBlock;
using testing_random::randomNewBlock;

// Dense reference filter: the textbook formulas on the full n x n matrix.
struct DenseReference {
  MatX C;
  std::vector<std::vector<uint8_t>> desc;
  int K() const { return static_cast<int>(desc.size()); }

  void reset(const Mat12& C0) {
    C = C0;
    desc.clear();
  }
  void predict(const Mat12& F, const Mat12& Q) {
    const int n = C.rows();
    MatX Fb = MatX::Identity(n, n);
    Fb.topLeftCorner<12, 12>() = F;
    C = Fb * C * Fb.transpose();
    C.topLeftCorner<12, 12>() += Q;
  }
  void add(const std::vector<NewLandmarkBlock>& blocks, int dlen) {
    const int n = C.rows(), m = static_cast<int>(blocks.size());
    MatX J = MatX::Zero(n + 3 * m, n);
    J.topRows(n).setIdentity();
    MatX Nz = MatX::Zero(n + 3 * m, n + 3 * m);
    for (int i = 0; i < m; ++i) {
      J.block(n + 3 * i, 0, 3, 6) = blocks[i].G_pose;
      Nz.block(n + 3 * i, n + 3 * i, 3, 3) = blocks[i].G_z * blocks[i].Cz * blocks[i].G_z.transpose();
      desc.emplace_back(blocks[i].descriptor, blocks[i].descriptor + dlen);
    }
    C = J * C * J.transpose() + Nz;
  }
  // Selects the kept rows/columns in the slot order of removal_plan.hpp
  // (whose own rule is pinned by test_removal_plan.cpp).
  void remove(const std::vector<int>& slots) {
    const std::vector<int> old_slot = oldSlotOfNew(K(), slots);
    std::vector<int> keep;
    for (int i = 0; i < 12; ++i) keep.push_back(i);
    for (int k : old_slot)
      for (int c = 0; c < 3; ++c) keep.push_back(12 + 3 * k + c);
    MatX D(keep.size(), keep.size());
    for (std::size_t r = 0; r < keep.size(); ++r)
      for (std::size_t c = 0; c < keep.size(); ++c) D(r, c) = C(keep[r], keep[c]);
    C = D;
    std::vector<std::vector<uint8_t>> d;
    for (int k : old_slot) d.push_back(desc[k]);
    desc = d;
  }
  // K = C H^T S^-1, C <- C - K S K^T, dx = K nu.
  void update(const std::vector<MeasurementBlock>& blocks, VecX* dx, double* nis) {
    const int n = C.rows(), m = 3 * static_cast<int>(blocks.size());
    MatX H = MatX::Zero(m, n), R = MatX::Zero(m, m);
    VecX nu(m);
    for (std::size_t j = 0; j < blocks.size(); ++j) {
      H.block(3 * j, 0, 3, 6) = blocks[j].H_pose;
      H.block(3 * j, 12 + 3 * blocks[j].slot, 3, 3) = blocks[j].H_landmark;
      R.block(3 * j, 3 * j, 3, 3) = blocks[j].R;
      nu.segment(3 * j, 3) = blocks[j].innovation;
    }
    const MatX S = H * C * H.transpose() + R;
    const MatX Sinv = S.inverse();
    const MatX Kg = C * H.transpose() * Sinv;
    C = C - Kg * S * Kg.transpose();
    *dx = Kg * nu;
    *nis = nu.dot(Sinv * nu);
  }
};

double maxAbs(const MatX& M) { return M.cwiseAbs().maxCoeff(); }

std::vector<int> distinctSlots(Rng& r, int K, int count) {
  std::vector<int> all(K);
  for (int k = 0; k < K; ++k) all[k] = k;
  std::shuffle(all.begin(), all.end(), r.gen);
  all.resize(std::min(count, K));
  return all;
}

// Adds `m` random landmarks to both.
void addRandom(Rng& r, CovarianceBackend* b, DenseReference* ref, int m, int dlen) {
  std::vector<std::vector<uint8_t>> store(m);
  std::vector<NewLandmarkBlock> blocks;
  for (int i = 0; i < m; ++i) {
    store[i] = r.bytes(dlen);
    blocks.push_back(randomNewBlock(r, store[i]));
  }
  ASSERT_EQ(b->addLandmarks(blocks), Status::kOk);
  ref->add(blocks, dlen);
}

TEST(CpuBackend, StructuredUpdateEqualsTextbookEkf) {
  Rng r(11);
  const int dlen = 32;
  auto b = makeCpuBackend(10, dlen);
  DenseReference ref;
  const Mat12 C0 = r.spd12(0.01);
  ASSERT_EQ(b->reset(C0), Status::kOk);
  ref.reset(C0);
  addRandom(r, b.get(), &ref, 6, dlen);
  // Start from the backend's own state so only the update is compared.
  ref.C = b->denseCovariance();
  const double trace_before = ref.C.trace();
  std::vector<MeasurementBlock> blocks;
  for (int s : {4, 0, 2, 5}) blocks.push_back(randomBlock(r, s, 0.02));
  VecX dx, dx_ref;
  double nis = 0, nis_ref = 0;
  ASSERT_EQ(b->update(blocks, &dx, &nis), Status::kOk);
  ref.update(blocks, &dx_ref, &nis_ref);
  const MatX C = b->denseCovariance();
  EXPECT_LT(maxAbs(C - ref.C) / maxAbs(ref.C), 1e-10);
  ASSERT_EQ(dx.size(), dx_ref.size());
  EXPECT_LT((dx - dx_ref).cwiseAbs().maxCoeff() / dx_ref.cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_NEAR(nis, nis_ref, 1e-10 * nis_ref);
  // The update must actually have reduced the uncertainty of the observed landmarks.
  EXPECT_LT(C.trace(), trace_before);
}

TEST(CpuBackend, RandomCyclesMatchDenseReferenceAndStayPsd) {
  Rng r(12);
  const int dlen = 16, cap = 30;
  auto b = makeCpuBackend(cap, dlen);
  DenseReference ref;
  const Mat12 C0 = r.spd12(0.01);
  ASSERT_EQ(b->reset(C0), Status::kOk);
  ref.reset(C0);
  for (int cycle = 0; cycle < 150; ++cycle) {
    // predict
    Mat12 F = Mat12::Identity();
    F.block<3, 3>(0, 3) = skew(r.v3(0.1));
    F.block<3, 3>(0, 6) = 0.1 * expSO3(r.v3(1.0));
    F.block<3, 3>(3, 3) = expSO3(r.v3(0.05)).transpose();
    F.block<3, 3>(3, 9) = 0.1 * Mat3::Identity();
    Mat12 Q = Mat12::Zero();
    Q.diagonal().segment<6>(6).setConstant(1e-3);
    ASSERT_EQ(b->predict(F, Q), Status::kOk);
    ref.predict(F, Q);
    // remove some
    if (b->numLandmarks() > 0 && r.i(0, 2) == 0) {
      const auto slots = distinctSlots(r, b->numLandmarks(), r.i(1, 4));
      ASSERT_EQ(b->removeLandmarks(slots), Status::kOk);
      ref.remove(slots);
    }
    // add some
    const int m = std::min(cap - b->numLandmarks(), r.i(0, 5));
    if (m > 0) addRandom(r, b.get(), &ref, m, dlen);
    // update some
    if (b->numLandmarks() > 0) {
      std::vector<MeasurementBlock> blocks;
      for (int s : distinctSlots(r, b->numLandmarks(), r.i(1, 8))) blocks.push_back(randomBlock(r, s, 0.01));
      VecX dx, dx_ref;
      double nis, nis_ref;
      ASSERT_EQ(b->update(blocks, &dx, &nis), Status::kOk);
      ref.update(blocks, &dx_ref, &nis_ref);
      ASSERT_LT((dx - dx_ref).cwiseAbs().maxCoeff(), 1e-8 * (1.0 + dx_ref.cwiseAbs().maxCoeff())) << cycle;
    }
    ASSERT_EQ(b->numLandmarks(), ref.K());
    const MatX C = b->denseCovariance();
    ASSERT_LT(maxAbs(C - ref.C), 1e-9 * maxAbs(ref.C)) << "cycle " << cycle;
    Eigen::SelfAdjointEigenSolver<MatX> es(C, Eigen::EigenvaluesOnly);
    ASSERT_GE(es.eigenvalues().minCoeff(), -1e-12 * maxAbs(C)) << "cycle " << cycle;
    const auto d = b->descriptors();
    for (int k = 0; k < ref.K(); ++k)
      ASSERT_EQ(0, std::memcmp(&d[k * dlen], ref.desc[k].data(), dlen)) << "descriptor of slot " << k;
    // Marginal and pose read-backs are sub-blocks of the same matrix.
    ASSERT_EQ(maxAbs(b->poseCovariance() - C.topLeftCorner<12, 12>()), 0.0);
  }
}

TEST(CpuBackend, RemoveThenReAddLeavesOtherBlocksBitwiseUntouched) {
  Rng r(13);
  const int dlen = 8;
  auto b = makeCpuBackend(12, dlen);
  DenseReference ref;
  ASSERT_EQ(b->reset(r.spd12(0.01)), Status::kOk);
  ref.reset(b->poseCovariance());
  addRandom(r, b.get(), &ref, 8, dlen);
  std::vector<MeasurementBlock> blocks;
  for (int s = 0; s < 8; ++s) blocks.push_back(randomBlock(r, s, 0.05));
  VecX dx;
  ASSERT_EQ(b->update(blocks, &dx), Status::kOk);  // now every block is non-trivially coupled
  const MatX before = b->denseCovariance();
  const auto desc_before = b->descriptors();

  ASSERT_EQ(b->removeLandmarks({3}), Status::kOk);
  const MatX after = b->denseCovariance();
  // Slot 3 is refilled by the last landmark (7); slots 0-2 and 4-6 stay.
  const int old_slot[7] = {0, 1, 2, 7, 4, 5, 6};
  std::vector<int> keep;
  for (int i = 0; i < 12; ++i) keep.push_back(i);
  for (int k : old_slot)
    for (int c = 0; c < 3; ++c) keep.push_back(12 + 3 * k + c);
  ASSERT_EQ(after.rows(), static_cast<int>(keep.size()));
  for (std::size_t i = 0; i < keep.size(); ++i)
    for (std::size_t j = 0; j < keep.size(); ++j) ASSERT_EQ(after(i, j), before(keep[i], keep[j]));

  std::vector<uint8_t> d = r.bytes(dlen);
  ASSERT_EQ(b->addLandmarks({randomNewBlock(r, d)}), Status::kOk);
  const MatX readded = b->denseCovariance();
  ASSERT_EQ(readded.rows(), before.rows());
  // Everything that existed before the re-addition is bit-for-bit the same.
  EXPECT_EQ(maxAbs(readded.topLeftCorner(after.rows(), after.cols()) - after), 0.0);
  const auto desc_after = b->descriptors();
  for (int k = 0; k < 7; ++k) EXPECT_EQ(0, std::memcmp(&desc_after[k * dlen], &desc_before[old_slot[k] * dlen], dlen));
  EXPECT_EQ(0, std::memcmp(&desc_after[7 * dlen], d.data(), dlen));  // the new one is last
}

// Only the landmarks above the new end move, into the lowest holes; the
// others keep their slot (and their blocks, bit for bit).
TEST(CpuBackend, RemovalFillsHolesFromTheTail) {
  Rng r(14);
  const int dlen = 4;
  auto b = makeCpuBackend(10, dlen);
  ASSERT_EQ(b->reset(r.spd12(0.01)), Status::kOk);
  std::vector<std::vector<uint8_t>> store;
  std::vector<NewLandmarkBlock> blocks;
  for (int i = 0; i < 8; ++i) store.push_back({uint8_t(i), uint8_t(i), uint8_t(i), uint8_t(i)});
  for (int i = 0; i < 8; ++i) blocks.push_back(randomNewBlock(r, store[i]));
  ASSERT_EQ(b->addLandmarks(blocks), Status::kOk);
  const auto cov_before = b->landmarkCovariances();
  ASSERT_EQ(b->removeLandmarks({6, 1, 4, 5}), Status::kOk);  // any order
  ASSERT_EQ(b->numLandmarks(), 4);
  const auto d = b->descriptors();
  const auto cov = b->landmarkCovariances();
  const int expect[] = {0, 7, 2, 3};
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(d[k * dlen], expect[k]);
    EXPECT_EQ(maxAbs(cov[k] - cov_before[expect[k]]), 0.0);
  }
  // Removing everything leaves the pose block alone.
  const Mat12 Cpp = b->poseCovariance();
  ASSERT_EQ(b->removeLandmarks({0, 1, 2, 3}), Status::kOk);
  EXPECT_EQ(b->numLandmarks(), 0);
  EXPECT_EQ(maxAbs(b->poseCovariance() - Cpp), 0.0);
}

struct Snapshot {
  MatX C;
  std::vector<uint8_t> d;
  int K;
  explicit Snapshot(const CovarianceBackend& b) : C(b.denseCovariance()), d(b.descriptors()), K(b.numLandmarks()) {}
  bool same(const CovarianceBackend& b) const {
    const MatX C2 = b.denseCovariance();
    return K == b.numLandmarks() && C.rows() == C2.rows() && (C.array() == C2.array()).all() && d == b.descriptors();
  }
};

TEST(CpuBackend, CapacityLimits) {
  Rng r(15);
  const int dlen = 8;
  auto b = makeCpuBackend(5, dlen);
  ASSERT_EQ(b->reset(r.spd12(0.01)), Status::kOk);
  EXPECT_EQ(b->capacity(), 5);
  std::vector<std::vector<uint8_t>> store(6, r.bytes(dlen));
  std::vector<NewLandmarkBlock> blocks;
  for (int i = 0; i < 4; ++i) blocks.push_back(randomNewBlock(r, store[i]));
  ASSERT_EQ(b->addLandmarks(blocks), Status::kOk);
  const Snapshot s(*b);
  EXPECT_EQ(b->addLandmarks({randomNewBlock(r, store[4]), randomNewBlock(r, store[5])}), Status::kCapacityExceeded);
  EXPECT_TRUE(s.same(*b));
  EXPECT_EQ(b->addLandmarks({randomNewBlock(r, store[4])}), Status::kOk);  // exactly full is fine
  EXPECT_EQ(b->numLandmarks(), 5);
  EXPECT_EQ(b->addLandmarks({randomNewBlock(r, store[5])}), Status::kCapacityExceeded);
  EXPECT_GE(b->memoryBytes(), sizeof(double) * 27 * 27);
}

TEST(CpuBackend, BadInputsReturnErrorAndLeaveStateUnchanged) {
  Rng r(16);
  const int dlen = 8;
  auto b = makeCpuBackend(8, dlen);
  ASSERT_EQ(b->reset(r.spd12(0.01)), Status::kOk);
  std::vector<std::vector<uint8_t>> store(6, r.bytes(dlen));
  std::vector<NewLandmarkBlock> nb;
  for (int i = 0; i < 5; ++i) nb.push_back(randomNewBlock(r, store[i]));
  ASSERT_EQ(b->addLandmarks(nb), Status::kOk);
  const Snapshot s(*b);
  VecX dx = VecX::Constant(3, 7.0);
  const VecX dx0 = dx;

  EXPECT_EQ(b->update({}, &dx), Status::kEmptyInput);
  auto nan_block = randomBlock(r, 1, 0.01);
  nan_block.innovation.x() = std::nan("");
  EXPECT_EQ(b->update({randomBlock(r, 0, 0.01), nan_block}, &dx), Status::kNonFinite);
  auto nan_h = randomBlock(r, 1, 0.01);
  nan_h.H_pose(2, 4) = std::numeric_limits<double>::infinity();
  EXPECT_EQ(b->update({nan_h}, &dx), Status::kNonFinite);
  EXPECT_EQ(b->update({randomBlock(r, 2, 0.01), randomBlock(r, 2, 0.01)}, &dx), Status::kDuplicateId);
  EXPECT_EQ(b->update({randomBlock(r, 5, 0.01)}, &dx), Status::kInvalidArgument);
  EXPECT_EQ(b->update({randomBlock(r, -1, 0.01)}, &dx), Status::kInvalidArgument);
  // Non-PD S: a measurement "covariance" far more negative than H C H^T is positive.
  auto neg = randomBlock(r, 3, 0.01);
  neg.R = -100.0 * Mat3::Identity();
  EXPECT_EQ(b->update({randomBlock(r, 0, 0.01), neg}, &dx), Status::kNotPositiveDefinite);
  EXPECT_TRUE((dx.array() == dx0.array()).all());
  EXPECT_TRUE(s.same(*b));

  auto bad = randomNewBlock(r, store[5]);
  bad.Cz(0, 0) = std::nan("");
  EXPECT_EQ(b->addLandmarks({bad}), Status::kNonFinite);
  bad = randomNewBlock(r, store[5]);
  bad.Cz = -Mat3::Identity();
  EXPECT_EQ(b->addLandmarks({randomNewBlock(r, store[5]), bad}), Status::kNotPositiveDefinite);
  bad = randomNewBlock(r, store[5]);
  bad.descriptor = nullptr;
  EXPECT_EQ(b->addLandmarks({bad}), Status::kInvalidArgument);
  EXPECT_EQ(b->removeLandmarks({1, 1}), Status::kDuplicateId);
  EXPECT_EQ(b->removeLandmarks({0, 5}), Status::kInvalidArgument);
  Mat12 F = Mat12::Identity();
  F(1, 2) = std::nan("");
  EXPECT_EQ(b->predict(F, Mat12::Zero()), Status::kNonFinite);
  Mat12 notpd = Mat12::Identity();
  notpd(4, 4) = -1;
  EXPECT_EQ(b->reset(notpd), Status::kNotPositiveDefinite);
  std::vector<Mat9> M;
  EXPECT_EQ(b->marginals({0, 9}, &M), Status::kInvalidArgument);
  EXPECT_TRUE(s.same(*b));
}

TEST(CpuBackend, MarginalsAreSubBlocksOfTheDenseCovariance) {
  Rng r(17);
  auto b = makeCpuBackend(6, 0);
  ASSERT_EQ(b->reset(r.spd12(0.01)), Status::kOk);
  std::vector<NewLandmarkBlock> nb;
  for (int i = 0; i < 4; ++i) nb.push_back(randomNewBlock(r, {}));
  ASSERT_EQ(b->addLandmarks(nb), Status::kOk);
  VecX dx;
  ASSERT_EQ(b->update({randomBlock(r, 1, 0.01), randomBlock(r, 3, 0.01)}, &dx), Status::kOk);
  const MatX C = b->denseCovariance();
  std::vector<Mat9> M;
  ASSERT_EQ(b->marginals({3, 0}, &M), Status::kOk);
  for (int j = 0; j < 2; ++j) {
    const int s = j == 0 ? 3 : 0;
    std::vector<int> idx = {0, 1, 2, 3, 4, 5, 12 + 3 * s, 13 + 3 * s, 14 + 3 * s};
    for (int a = 0; a < 9; ++a)
      for (int c = 0; c < 9; ++c) EXPECT_EQ(M[j](a, c), C(idx[a], idx[c]));
  }
}

TEST(CpuBackend, HammingMatchingEqualsBruteForce) {
  Rng r(18);
  for (int dlen : {32, 13}) {
    auto b = makeCpuBackend(50, dlen);
    ASSERT_EQ(b->reset(r.spd12(0.01)), Status::kOk);
    std::vector<std::vector<uint8_t>> store;
    for (int i = 0; i < 40; ++i) store.push_back(r.bytes(dlen));
    std::vector<NewLandmarkBlock> nb;
    for (int i = 0; i < 40; ++i) nb.push_back(randomNewBlock(r, store[i]));
    ASSERT_EQ(b->addLandmarks(nb), Status::kOk);
    std::vector<uint8_t> q;
    for (int i = 0; i < 10; ++i) {
      auto d = (i % 2 == 0) ? store[i * 3] : r.bytes(dlen);
      d[0] ^= 0x5;  // two bits flipped
      q.insert(q.end(), d.begin(), d.end());
    }
    std::vector<DescriptorMatch> out;
    ASSERT_EQ(b->matchDescriptors(q.data(), 10, &out), Status::kOk);
    ASSERT_EQ(out.size(), 10u);
    for (int i = 0; i < 10; ++i) {
      std::vector<std::pair<int, int>> dist;
      for (int k = 0; k < 40; ++k) {
        int d = 0;
        for (int t = 0; t < dlen; ++t) d += __builtin_popcount(q[i * dlen + t] ^ store[k][t]);
        dist.push_back({d, k});
      }
      std::sort(dist.begin(), dist.end());
      EXPECT_EQ(out[i].best_distance, dist[0].first);
      EXPECT_EQ(out[i].second_distance, dist[1].first);
      EXPECT_EQ(out[i].best_slot, dist[0].second);  // first slot wins ties
      if (i % 2 == 0) {
        EXPECT_EQ(out[i].best_slot, i * 3);
        EXPECT_EQ(out[i].best_distance, 2);
      }
    }
  }
}

TEST(BackendFactory, CpuAlwaysCudaOnlyWhenAvailable) {
  EskfSettings s;
  s.max_landmarks = 100;
  std::string err;
  auto cpu = makeBackend(s, 32, &err);
  ASSERT_TRUE(cpu) << err;
  EXPECT_STREQ(cpu->name(), makeCpuBackend(1, 0)->name());  // cpu-blas, or cpu-eigen without OpenBLAS
  EXPECT_EQ(cpu->capacity(), 100);
  EXPECT_EQ(cpu->descriptorLength(), 32);
  s.precision = Precision::kFp32;
  EXPECT_FALSE(makeBackend(s, 32, &err));
  EXPECT_FALSE(err.empty());
  s.precision = Precision::kFp64;
  s.max_landmarks = 0;
  err.clear();
  EXPECT_FALSE(makeBackend(s, 32, &err));
  EXPECT_NE(err.find("max_landmarks"), std::string::npos);
  s.max_landmarks = 100;
  s.backend = BackendKind::kCuda;
  std::string why;
  if (!cudaBackendAvailable(s.cuda_device, &why)) {
    EXPECT_FALSE(why.empty());
    err.clear();
    EXPECT_FALSE(makeBackend(s, 32, &err));
    EXPECT_FALSE(err.empty());
  }
}

}  // namespace
}  // namespace hapi_eskf
