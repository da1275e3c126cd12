// Two complete filters, one per backend, fed identical frames (CPU vs GPU:
// same inputs -> states equal to 1e-9 relative (FP64) over 100 iterations with
// additions and removals), through Eskf::processFrame: association, gating,
// update, eviction and initialisation all run on each backend.
#include "backend_pair.hpp"
#include "../basic_settings.hpp"

#include "hapi_eskf/eskf.hpp"
#include "hapi_eskf/jacobians.hpp"

namespace hapi_eskf {
namespace gputest {
namespace {

// A camera moving through a cloud of points; each frame sees the points in
// front of it within range, with 1 cm noise and a fixed descriptor per point.
struct World {
  std::vector<Vec3> points;
  std::vector<std::vector<uint8_t>> desc;
  Rng r{7};
  explicit World(int n) {
    for (int i = 0; i < n; ++i) {
      points.emplace_back(r.n(3.0), r.n(2.0), 4.0 + 12.0 * std::abs(r.n(1.0)));
      desc.push_back(r.bytes(32));
    }
  }
  StereoFrame frame(const PoseState& truth, double stamp, int max_meas) {
    StereoFrame f;
    f.stamp = stamp;
    f.descriptor_length = 32;
    const Mat3 Rt = truth.q.toRotationMatrix().transpose();
    for (std::size_t i = 0; i < points.size() && static_cast<int>(f.measurements.size()) < max_meas; ++i) {
      const Vec3 z = Rt * (points[i] - truth.p);
      if (z.z() < 1.0 || z.z() > 15.0 || std::abs(z.x()) > z.z() || std::abs(z.y()) > z.z()) continue;
      StereoMeasurement m;
      m.z = z + r.v3(0.01);
      m.Cz = 1e-4 * Mat3::Identity();
      m.frontend_id = static_cast<uint32_t>(i);
      m.response = static_cast<float>((i * 37) % 101);
      f.measurements.push_back(m);
      f.descriptors.insert(f.descriptors.end(), desc[i].begin(), desc[i].end());
    }
    return f;
  }
};

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
