// Two complete filters, one per backend, fed identical frames (CPU vs GPU:
// same inputs -> states equal to 1e-9 relative (FP64) over 100 iterations with
// additions and removals), through Eskf::processFrame: association, gating,
// update, eviction and initialisation all run on each backend.
#include "backend_pair.hpp"
#include "../basic_settings.hpp"
#include "../moving_camera_world.hpp"

#include "hapi_eskf/backend/pose_kinematics.hpp"
#include "hapi_eskf/eskf/eskf.hpp"
#include "hapi_eskf/eskf/storage_factory.hpp"

namespace hapi_eskf {
namespace gputest {
namespace {

using testing_world::World;

TEST(CudaFilter, HundredFramesMatchCpuFilter) {
  HAPI_REQUIRE_CUDA_DEVICE();
  EskfSettings s = testing_settings::basicFilter();
  s.max_landmarks = 150;  // small pool: eviction runs in most frames
  s.max_new_landmarks = 20;
  s.max_update_landmarks = 40;
  std::string err;
  EskfSettings sg = s;
  sg.backend = BackendKind::kCuda;
  auto gb = makeBackend(sg, 32, &err);
  ASSERT_TRUE(gb) << err;
  Eskf cpu(s, makeCpuBackend(s.max_landmarks, 32));
  Eskf gpu(sg, std::move(gb));
  EXPECT_STREQ(gpu.backend().name(), "cuda-fp64");

  World world(1500);
  PoseState truth;
  truth.v = Vec3(0.1, 0.0, 0.6);
  truth.w = Vec3(0.0, 0.08, 0.01);
  ASSERT_EQ(cpu.reset(PoseState(), 0.0), Status::kOk);
  ASSERT_EQ(gpu.reset(PoseState(), 0.0), Status::kOk);
  int removed = 0, added = 0, updated = 0;
  for (int f = 1; f <= 100; ++f) {
    truth = predictPose(truth, 0.1, s);
    const StereoFrame frame = world.frame(truth, 0.1 * f, 120);
    IterationReport rc, rg;
    const Status sc = cpu.processFrame(frame, &rc);
    const Status sgs = gpu.processFrame(frame, &rg);
    ASSERT_EQ(sc, sgs) << "frame " << f;
    ASSERT_EQ(rc.n_updated, rg.n_updated) << f;
    ASSERT_EQ(rc.n_added, rg.n_added) << f;
    ASSERT_EQ(rc.n_removed, rg.n_removed) << f;
    removed += rg.n_removed;
    added += rg.n_added;
    updated += rg.n_updated;
    ASSERT_EQ(cpu.landmarkIds(), gpu.landmarkIds()) << f;
    const PoseState& a = cpu.pose();
    const PoseState& b = gpu.pose();
    EXPECT_LE((b.p - a.p).norm(), 1e-9 * std::max(1.0, a.p.norm())) << f;
    EXPECT_LE(std::abs(a.q.angularDistance(b.q)), 1e-9) << f;
    EXPECT_LE((b.v - a.v).norm(), 1e-9 * std::max(1.0, a.v.norm())) << f;
    for (int k = 0; k < cpu.numLandmarks(); ++k)
      EXPECT_LE((gpu.landmarkPositions()[k] - cpu.landmarkPositions()[k]).norm(),
                1e-9 * std::max(1.0, cpu.landmarkPositions()[k].norm()))
          << f << " slot " << k;
    EXPECT_LE(relDiff(gpu.backend().denseCovariance(), cpu.backend().denseCovariance()), 1e-9) << f;
    EXPECT_EQ(gpu.backend().descriptors(), cpu.backend().descriptors()) << f;
    if (::testing::Test::HasFailure()) return;
  }
  // The run exercised what it claims to.
  EXPECT_GT(removed, 100);
  EXPECT_GT(added, 200);
  EXPECT_GT(updated, 1000);
  std::printf("100 frames: %d updates, %d added, %d removed, %d landmarks at the end\n", updated, added, removed,
              gpu.numLandmarks());
}

}  // namespace
}  // namespace gputest
}  // namespace hapi_eskf
