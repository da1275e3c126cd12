// A session's map between the back end and a map file (map_session.hpp):
// which settings can load a map, the pool saved in the published frame, and
// a read map into a fresh filter (docs/DESIGN.md "Map file").
#include "hapi_eskf/eskf/eskf.hpp"
#include "hapi_eskf/session/map_session.hpp"
#include "hapi_eskf/slam_backend_factory.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

namespace hapi_eskf {
namespace {

EskfSettings smallPool() {
  EskfSettings s;  // the tuned defaults (config/eskf.yaml)
  s.max_landmarks = 100;
  return s;
}

map_file::MapData mapOf(int landmarks) {
  map_file::MapData m;
  m.landmarks.resize(landmarks);
  for (int i = 0; i < landmarks; ++i) {
    m.landmarks[i].id = i + 1;
    m.landmarks[i].position = Vec3(0.1 * i, 0.0, 2.0);
    m.landmarks[i].covariance = 1e-4 * Mat3::Identity();
    m.landmarks[i].descriptor.assign(32, static_cast<uint8_t>(i));
  }
  return m;
}

bool names(const map_file::MapError& e, const std::string& what) {
  return e.fault == map_file::MapFault::kBadValue && e.message.find(what) != std::string::npos;
}

TEST(MapSession, LoadableOnlyWithTheEskfWithRansacRoomAndGravityForTheInertialModel) {
  const EskfSettings ok = smallPool();
  const int room = ok.max_landmarks - ok.max_new_landmarks;
  EXPECT_FALSE(map_file::checkLoadable(mapOf(room), ok));
  EXPECT_TRUE(names(map_file::checkLoadable(mapOf(room + 1), ok), "max_landmarks - max_new_landmarks"));
  EskfSettings s = ok;
  s.motion_model = MotionModelKind::kInertial;
  EXPECT_TRUE(names(map_file::checkLoadable(mapOf(1), s), "motion_model inertial needs the map's gravity"));
  map_file::MapData with_gravity = mapOf(1);
  with_gravity.gravity_direction = Vec3(0.0, 0.0, -1.0);
  EXPECT_FALSE(map_file::checkLoadable(with_gravity, s));
  s = ok;
  s.motion_model = MotionModelKind::kGyro;
  EXPECT_FALSE(map_file::checkLoadable(mapOf(1), s));
  s = ok;
  s.backend_algorithm = BackendAlgorithm::kSeif;
  EXPECT_TRUE(names(map_file::checkLoadable(mapOf(1), s), "backend_algorithm seif"));
  s = ok;
  s.ransac_iterations = 0;
  EXPECT_TRUE(names(map_file::checkLoadable(mapOf(1), s), "ransac_iterations"));
}

TEST(MapSession, PoolSavedInThePublishedFrameAndLoadedIntoAFreshFilter) {
  const EskfSettings s = smallPool();
  std::string error;
  std::unique_ptr<SlamBackend> session1 = makeSlamBackend(s, 32, CameraExtrinsic(), &error);
  ASSERT_TRUE(session1) << error;
  ASSERT_EQ(session1->reset(PoseState(), 0.0), Status::kOk);
  map_file::MapData out;
  int skipped = -1;
  EXPECT_TRUE(names(map_file::mapFromBackend(*session1, Eigen::Isometry3d::Identity(), {}, &out, &skipped),
                    "pool is empty"));
  // Session 1's pool: 20 landmarks (put in as a map: the filter's pool either way).
  const map_file::MapData truth = mapOf(20);
  ASSERT_FALSE(map_file::loadIntoBackend(truth, session1.get()));
  Eigen::Isometry3d T_out_world = Eigen::Isometry3d::Identity();
  T_out_world.linear() = Eigen::AngleAxisd(0.5, Vec3::UnitY()).toRotationMatrix();
  T_out_world.translation() = Vec3(1.0, -2.0, 0.5);
  map_file::MapData header;
  header.camera_frame = "cam";
  ASSERT_FALSE(map_file::mapFromBackend(*session1, T_out_world, header, &out, &skipped));
  EXPECT_EQ(skipped, 0);
  EXPECT_EQ(out.camera_frame, "cam");
  EXPECT_EQ(out.gravity_direction.norm(), 0.0);  // constant velocity: no gravity
  ASSERT_EQ(out.landmarks.size(), truth.landmarks.size());
  for (std::size_t i = 0; i < truth.landmarks.size(); ++i) {
    EXPECT_LT((out.landmarks[i].position - T_out_world * truth.landmarks[i].position).norm(), 1e-12) << i;
    const Mat3 R = T_out_world.linear();
    EXPECT_LT((out.landmarks[i].covariance - R * truth.landmarks[i].covariance * R.transpose()).norm(), 1e-12);
    EXPECT_EQ(out.landmarks[i].descriptor, truth.landmarks[i].descriptor);
  }
  // Into session 2's fresh filter: it waits for the map.
  std::unique_ptr<SlamBackend> session2 = makeSlamBackend(s, 32, CameraExtrinsic(), &error);
  ASSERT_EQ(session2->reset(PoseState(), 0.0), Status::kOk);
  ASSERT_FALSE(map_file::loadIntoBackend(out, session2.get()));
  EXPECT_EQ(session2->numLandmarks(), 20);
  EXPECT_TRUE(dynamic_cast<Eskf&>(*session2).awaitingMap());
  // Not twice (the pool is no longer empty): refused, nothing changes.
  EXPECT_TRUE(names(map_file::loadIntoBackend(out, session2.get()), "refused the map"));
  EXPECT_EQ(session2->numLandmarks(), 20);
}

TEST(MapSession, OtherBackEndsNeitherSaveNorLoad) {
  EskfSettings s = smallPool();
  s.backend_algorithm = BackendAlgorithm::kFastSlam2;
  std::string error;
  std::unique_ptr<SlamBackend> b = makeSlamBackend(s, 32, CameraExtrinsic(), &error);
  ASSERT_TRUE(b) << error;
  ASSERT_EQ(b->reset(PoseState(), 0.0), Status::kOk);
  map_file::MapData out;
  int skipped = 0;
  EXPECT_TRUE(names(map_file::mapFromBackend(*b, Eigen::Isometry3d::Identity(), {}, &out, &skipped), "fastslam2"));
  EXPECT_TRUE(names(map_file::loadIntoBackend(mapOf(3), b.get()), "fastslam2"));
  EXPECT_EQ(b->numLandmarks(), 0);
}

}  // namespace
}  // namespace hapi_eskf
