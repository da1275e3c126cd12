// Keyframes for place recognition (docs/DESIGN.md "Keyframes"): the index
// ranks the keyframe that saw the query's points first, the relocaliser
// places a camera near a keyframe with no pose hint, and nothing is placed
// on a surface that was never mapped or from a frame that cannot be; the
// recorder keeps a scan spaced and its keyframes place a later camera.
#include "hapi_eskf/keyframes/keyframe_recorder.hpp"
#include "hapi_eskf/keyframes/keyframe_relocaliser.hpp"

#include "keyframe_scene.hpp"

#include <gtest/gtest.h>

namespace hapi_eskf {
namespace {

// 2000 landmarks over 0.6 m x 0.6 m, keyframes on a 6 x 6 grid 25 cm above.
struct Mapped {
  test::KeyframeScene scene = test::makeKeyframeScene(2000, 0.6, 7);
  KeyframeRelocaliser reloc;
  std::mt19937 g{11};
  Mapped() {
    std::uint64_t id = 1;
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) {
        const Eigen::Isometry3d T = test::cameraAbove(-0.25 + 0.1 * i, -0.25 + 0.1 * j, 0.25, 0.3 * (i - j));
        const StereoFrame f = test::viewOf(scene, T, g, 16);
        EXPECT_TRUE(reloc.add(keyframeOf(id++, f, T, Mat6::Identity() * 1e-6)));
      }
  }
};

double rotationDeg(const Mat3& R) { return Eigen::AngleAxisd(R).angle() * 180.0 / M_PI; }

TEST(Keyframes, IndexRanksTheKeyframeThatSawThePointsFirst) {
  Mapped m;
  KeyframeIndex index;
  for (std::size_t k = 0; k < m.reloc.keyframes().size(); ++k) index.add(k, m.reloc.keyframes()[k]);
  // Near keyframe (2, 3): 1 cm and 0.05 rad away, other noise and bits.
  const Eigen::Isometry3d T = test::cameraAbove(-0.05 + 0.01, 0.05, 0.26, 0.3 * (2 - 3) + 0.05);
  const StereoFrame q = test::viewOf(m.scene, T, m.g, 16);
  ASSERT_GT(q.measurements.size(), 100u);
  const auto c = index.candidates(q.descriptors.data(), q.measurements.size(), 32, 36, 0);
  ASSERT_EQ(c.size(), 36u);
  EXPECT_EQ(c.front().keyframe, 2u * 6 + 3);
  // Keyframes whose view shares no point with the query's (>= 40 cm away:
  // the footprint is 29 x 21 cm) get chance votes only.
  for (const KeyframeVotes& v : c) {
    const int i = static_cast<int>(v.keyframe) / 6, j = static_cast<int>(v.keyframe) % 6;
    if (std::abs(i - 2) >= 4 || std::abs(j - 3) >= 4) EXPECT_LT(v.votes, c.front().votes / 20) << v.keyframe;
  }
}

TEST(Keyframes, PlacesACameraNearAKeyframeWithoutAHint) {
  Mapped m;
  int placed = 0;
  for (int trial = 0; trial < 10; ++trial) {
    const double x = -0.2 + 0.04 * trial, y = 0.15 - 0.03 * trial;
    const Eigen::Isometry3d T = test::cameraAbove(x, y, 0.24 + 0.003 * trial, 0.2 * trial - 1.0);
    const std::optional<KeyframeFit> fit = m.reloc.place(test::viewOf(m.scene, T, m.g, 16));
    if (!fit) continue;
    ++placed;
    const Eigen::Isometry3d E = T.inverse() * fit->T_map_cam;
    EXPECT_LT(E.translation().norm(), 2e-3) << "trial " << trial;
    EXPECT_LT(rotationDeg(E.linear()), 0.3) << "trial " << trial;
    EXPECT_GE(fit->inliers, 12);
  }
  EXPECT_EQ(placed, 10);
}

TEST(Keyframes, NothingPlacedOnASurfaceNeverMapped) {
  Mapped m;
  const test::KeyframeScene other = test::makeKeyframeScene(2000, 0.6, 99);  // other points, other descriptors
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::Isometry3d T = test::cameraAbove(-0.2 + 0.04 * trial, 0.0, 0.25, 0.1 * trial);
    EXPECT_FALSE(m.reloc.place(test::viewOf(other, T, m.g, 16))) << "trial " << trial;
  }
}

TEST(Keyframes, RefusesWhatCannotBeMatched) {
  Mapped m;
  StereoFrame empty;
  empty.descriptor_length = 32;
  EXPECT_FALSE(m.reloc.place(empty));
  // Another descriptor length (AKAZE's 61 bytes) is neither kept nor matched.
  Keyframe akaze;
  akaze.id = 999;
  akaze.descriptor_length = 61;
  akaze.points = {Vec3(0, 0, 0.3)};
  akaze.point_covariances = {Mat3::Identity() * 1e-6};
  akaze.descriptors.assign(61, 0);
  EXPECT_FALSE(m.reloc.add(akaze));
  StereoFrame q = test::viewOf(m.scene, test::cameraAbove(0, 0, 0.25, 0), m.g, 16);
  q.descriptor_length = 16;  // the same bytes read as 16-byte descriptors
  q.measurements.resize(q.descriptors.size() / 16, q.measurements.front());
  EXPECT_FALSE(m.reloc.place(q));
  // A keyframe whose arrays disagree is refused.
  Keyframe broken = m.reloc.keyframes().front();
  broken.point_covariances.pop_back();
  EXPECT_FALSE(m.reloc.add(broken));
  KeyframeRelocaliser none;
  EXPECT_FALSE(none.place(test::viewOf(m.scene, test::cameraAbove(0, 0, 0.25, 0), m.g, 16)));
}

// A scan recorded frame by frame keeps one keyframe per 2 cm of travel, and
// those keyframes, moved into another map frame, place a later camera there.
TEST(Keyframes, RecorderKeepsASpacedScanThatPlacesALaterCamera) {
  const test::KeyframeScene scene = test::makeKeyframeScene(2000, 0.6, 7);
  std::mt19937 g(5);
  KeyframeRecorder rec;
  int offered = 0, covariances_read = 0;
  for (; offered <= 80; ++offered) {  // 81 frames 5.1 mm apart
    const Eigen::Isometry3d T = test::cameraAbove(-0.2 + 0.0051 * offered, 0.0, 0.25, 0.0);
    rec.offer(test::viewOf(scene, T, g, 16, offered * 0.1), T, [&covariances_read] {
      ++covariances_read;
      return Mat6(Mat6::Identity() * 1e-6);
    });
  }
  EXPECT_EQ(rec.size(), 21u);  // every 4th frame (20.4 mm apart): 80 / 4 + 1
  EXPECT_EQ(covariances_read, 21);  // the back end's covariance is read for kept frames only
  // A frame with too few points is never kept.
  const Eigen::Isometry3d T_sparse = test::cameraAbove(0.25, 0.25, 0.25, 0.0);
  StereoFrame sparse = test::viewOf(scene, T_sparse, g, 16);
  sparse.measurements.resize(5);
  sparse.descriptors.resize(5 * 32);
  EXPECT_FALSE(rec.offer(sparse, T_sparse, [] { return Mat6(Mat6::Identity()); }));

  // The same keyframes in a map frame turned 30 deg and moved 10 cm.
  Eigen::Isometry3d T_map_world = Eigen::Isometry3d::Identity();
  T_map_world.linear() = Eigen::AngleAxisd(0.5, Vec3(0.2, -0.3, 1.0).normalized()).toRotationMatrix();
  T_map_world.translation() = Vec3(0.1, -0.05, 0.02);
  Mat6 C = Mat6::Identity() * 1e-6;
  C(0, 0) = 4e-6;
  KeyframeRecorder one;
  const Eigen::Isometry3d T0 = test::cameraAbove(0, 0, 0.25, 0);
  ASSERT_TRUE(one.offer(test::viewOf(scene, T0, g, 16), T0, [&] { return C; }));
  const Keyframe moved = one.keyframes(T_map_world).front();
  const Mat3 R = T_map_world.linear();
  EXPECT_TRUE((moved.pose_covariance.topLeftCorner<3, 3>().isApprox(R * C.topLeftCorner<3, 3>() * R.transpose())));
  EXPECT_TRUE((moved.pose_covariance.bottomRightCorner<3, 3>().isApprox(C.bottomRightCorner<3, 3>())));

  KeyframeRelocaliser reloc;
  for (Keyframe& k : rec.keyframes(T_map_world)) ASSERT_TRUE(reloc.add(std::move(k)));
  const Eigen::Isometry3d T_world = test::cameraAbove(0.052, 0.01, 0.255, 0.05);
  const std::optional<KeyframeFit> fit = reloc.place(test::viewOf(scene, T_world, g, 16));
  ASSERT_TRUE(fit);
  const Eigen::Isometry3d E = (T_map_world * T_world).inverse() * fit->T_map_cam;
  EXPECT_LT(E.translation().norm(), 2e-3);
  EXPECT_LT(rotationDeg(E.linear()), 0.3);

  // A full store counts what it could not keep; a reset empties it.
  KeyframeRecorderSettings small;
  small.max_keyframes = 2;
  KeyframeRecorder full(small);
  for (int i = 0; i < 4; ++i) {
    const Eigen::Isometry3d T = test::cameraAbove(-0.1 + 0.05 * i, 0.0, 0.25, 0.0);
    full.offer(test::viewOf(scene, T, g, 16), T, [] { return Mat6(Mat6::Identity() * 1e-6); });
  }
  EXPECT_EQ(full.size(), 2u);
  EXPECT_EQ(full.notKeptFull(), 2u);
  full.clear();
  EXPECT_EQ(full.size(), 0u);
}

}  // namespace
}  // namespace hapi_eskf
