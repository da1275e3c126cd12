// The SEIF back end (seif/seif_storage.hpp) on a short simulated stream
// (sim_scenario.hpp): without sparsification it equals the ES-EKF to
// rounding; sparsified, its pose and map stay within bounds, the active set
// within its bound, its covariances PSD; bad input leaves it unchanged. The
// sparsification step against the textbook formula.
#include "basic_settings.hpp"
#include "hapi_eskf/eskf/eskf.hpp"
#include "hapi_eskf/seif/seif_storage.hpp"
#include "hapi_eskf/seif/sparsification.hpp"
#include "hapi_eskf/slam_backend_factory.hpp"
#include "sim_scenario.hpp"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numeric>
#include <random>

namespace hapi_eskf {
namespace {

struct Stream {
  std::vector<StereoFrame> frames;
  std::vector<PoseState> truth;
  sim::World world;
};

EskfSettings streamSettings() {
  EskfSettings s = testing_settings::basicFilter();
  s.ransac_iterations = 100;  // the shared association with its RANSAC stage
  s.max_landmarks = 120;      // the pool fills: removals (marginalisation) are exercised
  s.max_new_landmarks = 20;
  s.bootstrap_landmarks = 60;
  s.max_update_landmarks = 40;
  s.sigma_acceleration = 0.2;
  s.sigma_angular_acceleration = 0.05;
  s.initial_sigma_position = 1e-6;
  s.initial_sigma_orientation = 1e-6;
  s.initial_sigma_velocity = 0.1;
  s.initial_sigma_angular_velocity = 0.05;
  return s;
}

Stream makeStream(int n_frames, const EskfSettings& s, unsigned seed) {
  std::mt19937 rng(seed);
  const sim::StereoRig rig;
  Stream st;
  st.world = sim::randomWorld(rng, 6000, Vec3(-20, -20, -20), Vec3(20, 20, 20));
  PoseState truth;
  truth.v = Vec3(0, 0, 1.0);
  truth.w = Vec3(0, 0.1, 0);
  for (int k = 0; k < n_frames; ++k) {
    if (k > 0) truth = sim::truthStep(truth, 0.1, s, rng);
    st.truth.push_back(truth);
    st.frames.push_back(sim::makeFrame(st.world, truth, rig, 0.1 * k, 4, rng));
  }
  return st;
}

std::unique_ptr<SlamBackend> make(const EskfSettings& s) {
  std::string err;
  auto b = makeSlamBackend(s, 32, CameraExtrinsic(), &err);
  EXPECT_TRUE(b) << err;
  return b;
}

PoseState start(const Stream& st) {
  PoseState p = st.truth.front();
  return p;
}

// sparsifiedInformation against Thrun's formula written out,
// Omega - T(m0) + T(x, m0) - T(x) with T(S) = Omega_.S Omega_SS^-1 Omega_S.,
// on random information matrices (12 and 18 pose rows, m+ and m0 of several
// sizes): equal to 1e-9 relative, the x-m0 links zero.
TEST(SeifSparsification, EqualsTheTextbookFormula) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int P : {kCameraMotionDim, kMaxPoseDim})
    for (int keep : {0, 3, 20})
      for (int drop : {1, 7, 40}) {
        const int n = P + 3 * (keep + drop), m0 = P + 3 * keep;
        Eigen::MatrixXd X(n, n + 5);
        for (int r = 0; r < n; ++r)
          for (int c = 0; c < n + 5; ++c) X(r, c) = g(rng);
        const Eigen::MatrixXd Om = X * X.transpose() + Eigen::MatrixXd::Identity(n, n);
        auto T = [&](const std::vector<int>& S) {
          const Eigen::MatrixXd OS = Om(Eigen::all, S);
          const Eigen::MatrixXd SS = Om(S, S);
          return Eigen::MatrixXd(OS * SS.llt().solve(OS.transpose()));
        };
        std::vector<int> x(P), m0_idx(n - m0), xm0;
        std::iota(x.begin(), x.end(), 0);
        std::iota(m0_idx.begin(), m0_idx.end(), m0);
        xm0 = x;
        xm0.insert(xm0.end(), m0_idx.begin(), m0_idx.end());
        const Eigen::MatrixXd ref = Om - T(m0_idx) + T(xm0) - T(x);
        Eigen::MatrixXd out;
        ASSERT_TRUE(seif::sparsifiedInformation(Om, P, 3 * keep, &out));
        const double scale = Om.cwiseAbs().maxCoeff();
        EXPECT_LT((out - ref).cwiseAbs().maxCoeff(), 1e-9 * scale) << "P " << P << " keep " << keep << " drop " << drop;
        EXPECT_LT(ref.block(0, m0, P, n - m0).cwiseAbs().maxCoeff(), 1e-9 * scale);  // what the formula promises
        EXPECT_EQ(out.block(0, m0, P, n - m0).cwiseAbs().maxCoeff(), 0.0);
        EXPECT_EQ(out.block(m0, 0, n - m0, P).cwiseAbs().maxCoeff(), 0.0);
      }
}

TEST(Seif, WithoutSparsificationEqualsTheEskf) {
  EskfSettings s = streamSettings();
  const Stream st = makeStream(50, s, 7);
  s.backend_algorithm = BackendAlgorithm::kEskf;
  auto ekf = make(s);
  s.backend_algorithm = BackendAlgorithm::kSeif;
  s.seif.max_active_landmarks = 0;  // no sparsification
  auto seif = make(s);
  ASSERT_TRUE(ekf && seif);
  EXPECT_STREQ(seif->name(), "seif");
  EXPECT_STREQ(ekf->name(), "eskf");
  ASSERT_EQ(ekf->reset(start(st), 0.0), Status::kOk);
  ASSERT_EQ(seif->reset(start(st), 0.0), Status::kOk);
  int removed = 0, updated = 0;
  double max_dp = 0, max_dtheta = 0, max_dm = 0, max_dcov = 0;
  for (const StereoFrame& f : st.frames) {
    IterationReport ra, rb;
    ASSERT_EQ(ekf->processFrame(f, &ra), Status::kOk);
    ASSERT_EQ(seif->processFrame(f, &rb), Status::kOk);
    // The same decisions (association, gate, bookkeeping) ...
    ASSERT_EQ(ra.n_candidates, rb.n_candidates);
    ASSERT_EQ(ra.n_gated_out, rb.n_gated_out);
    ASSERT_EQ(ra.n_updated, rb.n_updated);
    ASSERT_EQ(ra.n_added, rb.n_added);
    ASSERT_EQ(ra.n_removed, rb.n_removed);
    EXPECT_NEAR(ra.mean_nis, rb.mean_nis, 1e-6 * (1 + ra.mean_nis));
    removed += ra.n_removed;
    updated += ra.n_updated;
    // ... and the same estimate and covariances, to rounding.
    const PoseState a = ekf->pose(), b = seif->pose();
    max_dp = std::max(max_dp, (a.p - b.p).norm());
    max_dtheta = std::max(max_dtheta, a.q.angularDistance(b.q));
    const Mat6 Ca = ekf->cameraPoseCovariance(), Cb = seif->cameraPoseCovariance();
    max_dcov = std::max(max_dcov, (Ca - Cb).norm() / Ca.norm());
    const auto la = ekf->landmarks(), lb = seif->landmarks();
    ASSERT_EQ(la.size(), lb.size());
    for (std::size_t k = 0; k < la.size(); ++k) {
      ASSERT_EQ(la[k].id, lb[k].id);
      max_dm = std::max(max_dm, (la[k].position - lb[k].position).norm());
      max_dcov = std::max(max_dcov, (la[k].covariance - lb[k].covariance).norm() / la[k].covariance.norm());
    }
  }
  EXPECT_GT(removed, 0);  // the pool was full: marginalisation ran
  EXPECT_GT(updated, 500);
  EXPECT_LT(max_dp, 1e-9);
  EXPECT_LT(max_dtheta, 1e-9);
  EXPECT_LT(max_dm, 1e-8);
  EXPECT_LT(max_dcov, 1e-6);
  std::printf("seif vs eskf: max |dp| %.2e m, |dtheta| %.2e rad, |dm| %.2e m, rel. covariance %.2e\n", max_dp,
              max_dtheta, max_dm, max_dcov);
}

bool isPsd(const Eigen::MatrixXd& C) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (C + C.transpose()));
  return es.eigenvalues().minCoeff() > -1e-12 * std::max(1.0, es.eigenvalues().maxCoeff());
}

// RMS distance of the map to the nearest true point, counting landmarks seen
// at least 3 times (a landmark seen once keeps its stereo depth noise: ~1.8 m
// along the ray at 14 m with this rig).
double mapRms(const std::vector<LandmarkInfo>& lm, const sim::World& world, int* n_out) {
  double map2 = 0;
  int n = 0;
  for (const LandmarkInfo& l : lm) {
    if (l.times_observed < 3) continue;
    double best = std::numeric_limits<double>::infinity();
    for (const Vec3& p : world.points) best = std::min(best, (p - l.position).squaredNorm());
    map2 += best;
    ++n;
  }
  *n_out = n;
  return n > 0 ? std::sqrt(map2 / n) : 0.0;
}

struct Accuracy {
  double pos_rms = 0, rot_rms = 0, map_rms = 0;
  int n_map = 0;
};

// Runs the SEIF with the given active bound on the stream and checks, every
// frame, the bound and PSD covariances.
Accuracy runSeif(const Stream& st, EskfSettings s, int max_active) {
  s.backend_algorithm = BackendAlgorithm::kSeif;
  s.seif.max_active_landmarks = max_active;
  s.seif.recovery_landmarks = 20;
  std::string err;
  auto storage = seif::makeSeifStorage(s, 32, &err);
  EXPECT_TRUE(storage) << err;
  const auto* seif_storage = dynamic_cast<const seif::SeifStorage*>(storage.get());
  Eskf f(s, std::move(storage));
  EXPECT_EQ(f.reset(start(st), 0.0), Status::kOk);
  double pos2 = 0, rot2 = 0;
  for (std::size_t k = 0; k < st.frames.size(); ++k) {
    EXPECT_EQ(f.processFrame(st.frames[k]), Status::kOk) << "frame " << k;
    if (max_active > 0) EXPECT_LE(seif_storage->numActive(), max_active);
    const auto e = sim::poseError(st.truth[k], f.pose());
    pos2 += e.head<3>().squaredNorm();
    rot2 += e.tail<3>().squaredNorm();
    EXPECT_TRUE(isPsd(f.cameraPoseCovariance()));
    EXPECT_GT(f.cameraPoseCovariance().diagonal().minCoeff(), 0.0);
  }
  const auto lm = f.landmarks();
  EXPECT_GT(lm.size(), 50u);
  for (const LandmarkInfo& l : lm) {
    EXPECT_TRUE(isPsd(l.covariance));
    EXPECT_GT(l.covariance.trace(), 0.0);
  }
  EXPECT_TRUE(isPsd(f.backend().denseCovariance()));
  Accuracy a;
  a.pos_rms = std::sqrt(pos2 / st.frames.size());
  a.rot_rms = std::sqrt(rot2 / st.frames.size());
  a.map_rms = mapRms(lm, st.world, &a.n_map);
  return a;
}

TEST(Seif, SparsifiedStaysAccurateBoundedAndPsd) {
  const EskfSettings s = streamSettings();
  const Stream st = makeStream(60, s, 11);
  const Accuracy exact = runSeif(st, s, 0);  // = the ES-EKF (test above)
  const Accuracy sparse = runSeif(st, s, 25);
  std::printf("seif exact: position RMS %.4f m, rotation %.5f rad, map %.3f m (%d)\n", exact.pos_rms, exact.rot_rms,
              exact.map_rms, exact.n_map);
  std::printf("seif 25 active: position RMS %.4f m, rotation %.5f rad, map %.3f m (%d)\n", sparse.pos_rms,
              sparse.rot_rms, sparse.map_rms, sparse.n_map);
  // 6 m travelled through points 1.5-14 m away: absolute bounds, and the
  // sparsified filter close to the exact one.
  EXPECT_LT(sparse.pos_rms, 0.05);
  EXPECT_LT(sparse.rot_rms, 0.005);
  EXPECT_LT(sparse.map_rms, 0.5);  // landmarks at up to 14 m carry ~1 m of stereo depth noise
  EXPECT_GT(sparse.n_map, 30);
  EXPECT_LT(sparse.pos_rms, 2.0 * exact.pos_rms + 0.01);
  EXPECT_LT(sparse.rot_rms, 2.0 * exact.rot_rms + 0.001);
  EXPECT_LT(sparse.map_rms, 1.2 * exact.map_rms + 0.02);
}

TEST(Seif, BadInputLeavesTheStateUnchanged) {
  EskfSettings s = streamSettings();
  const Stream st = makeStream(12, s, 3);
  s.backend_algorithm = BackendAlgorithm::kSeif;
  s.seif.max_active_landmarks = 25;
  auto f = make(s);
  ASSERT_TRUE(f);
  ASSERT_EQ(f->reset(start(st), 0.0), Status::kOk);
  for (int k = 0; k < 10; ++k) ASSERT_EQ(f->processFrame(st.frames[k]), Status::kOk);
  const PoseState p0 = f->pose();
  const Mat6 C0 = f->cameraPoseCovariance();
  const auto m0 = f->landmarks();
  auto unchanged = [&] {
    const auto m1 = f->landmarks();
    if (m1.size() != m0.size()) return false;
    for (std::size_t k = 0; k < m0.size(); ++k)
      if (m1[k].position != m0[k].position || m1[k].covariance != m0[k].covariance) return false;
    return f->pose().p == p0.p && f->pose().q.coeffs() == p0.q.coeffs() && f->cameraPoseCovariance() == C0;
  };
  StereoFrame nan = st.frames[10];
  nan.measurements[0].z.x() = std::nan("");
  EXPECT_EQ(f->processFrame(nan), Status::kNonFinite);
  EXPECT_TRUE(unchanged());
  StereoFrame old = st.frames[10];
  old.stamp = 0.5;  // before the filter time
  EXPECT_EQ(f->processFrame(old), Status::kInvalidArgument);
  EXPECT_TRUE(unchanged());
  StereoFrame bad_desc = st.frames[10];
  bad_desc.descriptors.pop_back();
  EXPECT_EQ(f->processFrame(bad_desc), Status::kInvalidArgument);
  EXPECT_TRUE(unchanged());
  StereoFrame not_pd = st.frames[10];
  not_pd.measurements[0].Cz = -Mat3::Identity();
  EXPECT_EQ(f->processFrame(not_pd), Status::kNotPositiveDefinite);
  EXPECT_TRUE(unchanged());
  EXPECT_EQ(f->addImu(ImuSample{1.05, Vec3::Zero(), Vec3(0, 0, 9.81)}), Status::kInvalidArgument);  // no IMU model
  EXPECT_TRUE(unchanged());
  EXPECT_EQ(f->processFrame(st.frames[10]), Status::kOk);
}

TEST(SlamBackendFactory, UnbuiltAlgorithmsAreAnErrorNotAStub) {
  for (BackendAlgorithm a : {BackendAlgorithm::kGraph, BackendAlgorithm::kFastSlam2}) {
    std::string why;
    if (slamBackendBuilt(a, &why)) continue;  // built into this library: nothing to check here
    EskfSettings s;
    s.backend_algorithm = a;
    std::string err;
    EXPECT_EQ(makeSlamBackend(s, 32, CameraExtrinsic(), &err), nullptr);
    EXPECT_NE(err.find("not built"), std::string::npos) << err;
  }
  EXPECT_TRUE(slamBackendBuilt(BackendAlgorithm::kEskf, nullptr));
  EXPECT_TRUE(slamBackendBuilt(BackendAlgorithm::kSeif, nullptr));
}

}  // namespace
}  // namespace hapi_eskf
