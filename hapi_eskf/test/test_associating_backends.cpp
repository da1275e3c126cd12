// graph and fastslam2 through the back-end interface (slam_backend.hpp): the
// factory builds them, the shared association finds the landmarks by their
// descriptors on the synthetic globe (globe_run.hpp), and each back end
// stays within pose and map error bounds with PSD covariances; bad frames
// change nothing.
#include "globe_run.hpp"
#include "hapi_eskf/slam_backend_factory.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>
#include <vector>

namespace hapi_eskf {
namespace {

EskfSettings settingsFor(BackendAlgorithm a) {
  EskfSettings s;
  s.backend_algorithm = a;
  s.max_landmarks = 300;
  s.measurement_angular_sigma = 0.0;  // the simulation has no re-detection noise
  s.fastslam.num_particles = 30;
  return s;
}

void runOnGlobe(BackendAlgorithm a) {
  std::string why;
  if (!slamBackendBuilt(a, &why)) GTEST_SKIP() << why;
  const sim::GlobeRun run = sim::makeGlobeRun(11, 1500, 80, 1.0);
  std::string err;
  auto b = makeSlamBackend(settingsFor(a), 32, CameraExtrinsic(), &err);
  ASSERT_NE(b, nullptr) << err;
  EXPECT_STREQ(b->name(), toString(a));
  ASSERT_EQ(b->reset(run.truth[0], 0.0), Status::kOk);
  double max_pos = 0, max_rot = 0;
  bool psd = true;
  int updated = 0;
  for (std::size_t k = 0; k < run.frames.size(); ++k) {
    IterationReport rep;
    ASSERT_EQ(b->processFrame(run.frames[k], &rep), Status::kOk) << k;
    // graph: the window solve of this frame is merged before the next one,
    // so the figures do not depend on how fast the background solver runs.
    b->settle();
    updated += rep.n_updated;
    const auto e = sim::poseError(run.truth[k], b->pose());
    max_pos = std::max(max_pos, e.head<3>().norm());
    max_rot = std::max(max_rot, e.tail<3>().norm());
    psd = psd && sim::isPsd(b->cameraPoseCovariance());
  }
  std::vector<Vec3> pts;
  const auto lms = b->landmarks();
  EXPECT_EQ(static_cast<int>(lms.size()), b->numLandmarks());
  for (const LandmarkInfo& l : lms) {
    pts.push_back(l.position);
    psd = psd && sim::isPsd(l.covariance);
  }
  const double map_rms = sim::sphereRms(run.globe, pts);
  std::printf("%s through SlamBackend: max pos err %.4f m, max rot err %.4f rad, map rms %.4f m (%zu landmarks), "
              "%d updates\n",
              b->name(), max_pos, max_rot, map_rms, pts.size(), updated);
  EXPECT_GT(updated, 20 * static_cast<int>(run.frames.size()));
  // Settled after every frame (above): the same figures on any machine.
  EXPECT_LT(max_pos, 0.08);
  EXPECT_LT(max_rot, 0.03);
  EXPECT_LT(map_rms, 0.012);
  EXPECT_TRUE(psd);

  // Bad frames: rejected, nothing changes.
  const PoseState p0 = b->pose();
  const auto l0 = b->landmarks();
  StereoFrame good = run.frames.back();
  good.stamp += 0.1;
  std::vector<std::pair<StereoFrame, Status>> bad;
  StereoFrame f = good;
  f.measurements[3].z.y() = std::nan("");
  bad.emplace_back(f, Status::kNonFinite);
  f = good;
  f.measurements[3].Cz = -Mat3::Identity();
  bad.emplace_back(f, Status::kNotPositiveDefinite);
  f = good;
  f.measurements[3].frontend_id = f.measurements[2].frontend_id;
  bad.emplace_back(f, Status::kDuplicateId);
  f = good;
  f.descriptors.pop_back();
  bad.emplace_back(f, Status::kInvalidArgument);
  f = good;
  f.stamp = 1.0;
  bad.emplace_back(f, Status::kInvalidArgument);
  for (const auto& fb : bad) {
    EXPECT_EQ(b->processFrame(fb.first), fb.second);
    EXPECT_EQ(b->pose().p, p0.p);
    const auto l = b->landmarks();
    ASSERT_EQ(l.size(), l0.size());
    for (std::size_t i = 0; i < l.size(); ++i) EXPECT_EQ(l[i].position, l0[i].position);
  }
  EXPECT_EQ(b->addImu(ImuSample{good.stamp, Vec3::Zero(), Vec3(0, 0, 9.81)}), Status::kInvalidArgument);
}

TEST(AssociatingBackends, FastSlam2OnGlobe) { runOnGlobe(BackendAlgorithm::kFastSlam2); }
TEST(AssociatingBackends, GraphOnGlobe) { runOnGlobe(BackendAlgorithm::kGraph); }

// settle() after every frame (what compare_backends does): graph's window
// solutions are merged before the next frame, so a replay gives the same
// poses and map every time, whatever the machine's speed; without it the
// background solver's timing changes the figures (the bounds above).
TEST(AssociatingBackends, GraphSettledReplayIsDeterministic) {
  if (!slamBackendBuilt(BackendAlgorithm::kGraph, nullptr)) GTEST_SKIP() << "graph not built";
  const sim::GlobeRun run = sim::makeGlobeRun(12, 1500, 40, 1.0);
  auto replay = [&](std::vector<PoseState>* poses, std::vector<LandmarkInfo>* map) {
    std::string err;
    auto b = makeSlamBackend(settingsFor(BackendAlgorithm::kGraph), 32, CameraExtrinsic(), &err);
    ASSERT_NE(b, nullptr) << err;
    ASSERT_EQ(b->reset(run.truth[0], 0.0), Status::kOk);
    for (std::size_t k = 0; k < run.frames.size(); ++k) {
      ASSERT_EQ(b->processFrame(run.frames[k]), Status::kOk) << k;
      // Slow the frame thread down in the first replay only: the background
      // solver then has time a fast replay does not give it.
      if (poses->empty() && k % 3 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
      b->settle();
      poses->push_back(b->pose());
    }
    *map = b->landmarks();
  };
  std::vector<PoseState> p1, p2;
  std::vector<LandmarkInfo> m1, m2;
  replay(&p1, &m1);
  replay(&p2, &m2);
  // The same to rounding (the solver's BLAS may sum in another order from
  // run to run); the background timing moves them by centimetres.
  const double kRounding = 1e-7;
  ASSERT_EQ(p1.size(), p2.size());
  for (std::size_t k = 0; k < p1.size(); ++k) {
    EXPECT_LT((p1[k].p - p2[k].p).norm(), kRounding) << k;
    EXPECT_LT(p1[k].q.angularDistance(p2[k].q), kRounding) << k;
  }
  ASSERT_EQ(m1.size(), m2.size());
  for (std::size_t i = 0; i < m1.size(); ++i) {
    EXPECT_EQ(m1[i].id, m2[i].id);
    EXPECT_LT((m1[i].position - m2[i].position).norm(), kRounding) << m1[i].id;
  }
}

TEST(AssociatingBackends, ImuModelsAreRefused) {
  for (BackendAlgorithm a : {BackendAlgorithm::kFastSlam2, BackendAlgorithm::kGraph}) {
    if (!slamBackendBuilt(a, nullptr)) continue;
    EskfSettings s = settingsFor(a);
    s.motion_model = MotionModelKind::kInertial;
    std::string err;
    EXPECT_EQ(makeSlamBackend(s, 32, CameraExtrinsic(), &err), nullptr);
    EXPECT_NE(err.find("constant_velocity"), std::string::npos) << err;
  }
}

}  // namespace
}  // namespace hapi_eskf
