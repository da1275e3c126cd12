// Coming back to the same scene (docs/DESIGN.md "Map file"): session 1 maps
// a scene and saves its pool as a map file; session 2 starts at another
// pose with no hint, loads the file, holds its frames until a RANSAC fit of
// its measurements against the loaded landmarks places it in the map, then
// tracks in the map frame and adds landmarks beyond the loaded ones; where
// the saved pool no longer holds an area's landmarks, the map's keyframes
// place the camera. A session on another scene (other points, other
// descriptors) must never relocalise in the map.
#include "hapi_eskf/eskf/eskf.hpp"
#include "hapi_eskf/keyframes/keyframe_recorder.hpp"
#include "hapi_eskf/map_file/map_landmarks.hpp"
#include "hapi_eskf/map_file/map_reader.hpp"
#include "hapi_eskf/session/map_session.hpp"
#include "hapi_eskf/map_file/map_writer.hpp"
#include "basic_settings.hpp"
#include "inertial_scenario.hpp"
#include "keyframe_scene.hpp"
#include "sim_scenario.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <unistd.h>

namespace hapi_eskf {
namespace {

// Session 1 fills a pool of 400; session 2 holds the map and room to grow.
EskfSettings filterSettings(int max_landmarks) {
  EskfSettings s;  // the tuned defaults (config/eskf.yaml): RANSAC, bootstrap, relocalisation on
  s.max_landmarks = max_landmarks;
  s.max_update_landmarks = 60;
  return s;
}

map_file::MapCalibration rigCalibration(const sim::StereoRig& rig) {
  map_file::MapCalibration c;
  c.width = 640;
  c.height = 480;
  c.fx = c.fy = rig.focal_px;
  c.cx = 320;
  c.cy = 240;
  c.baseline = rig.baseline_m;
  return c;
}

// Session 1: from the world origin along +x, saving the pool at the end.
std::string mapScene(const sim::World& scene, const sim::StereoRig& rig, std::mt19937& rng) {
  const EskfSettings s = filterSettings(400);
  Eskf f(s, makeCpuBackend(s.max_landmarks, 32));
  PoseState truth;
  truth.v = Vec3(0.2, 0.0, 0.0);
  EXPECT_EQ(f.reset(truth, 0.0), Status::kOk);
  for (int k = 1; k <= 40; ++k) {
    truth = predictPose(truth, 0.1, s);
    EXPECT_EQ(f.processFrame(sim::makeFrame(scene, truth, rig, 0.1 * k, 4, rng)), Status::kOk);
  }
  const auto e = sim::poseError(truth, f.pose());
  std::printf("session 1: %d landmarks, final error %.2f mm %.3f deg\n", f.numLandmarks(), 1e3 * e.head<3>().norm(),
              e.tail<3>().norm() * 180 / M_PI);
  map_file::MapData map;
  map.camera_frame = "stereo_left_optical_frame";
  map.calibration = rigCalibration(rig);
  int skipped = 0;
  map.landmarks = map_file::toMapLandmarks(f.landmarks(), f.landmarkDescriptors(), 32, &skipped);
  EXPECT_EQ(skipped, 0);
  const std::string path = ::testing::TempDir() + "map_relocalise_" + std::to_string(::getpid()) + ".hmap";
  const map_file::MapError err = map_file::writeMapFile(path, map);
  EXPECT_FALSE(err) << err.message;
  return path;
}

struct Session {
  int loaded = 0, landmarks_at_end = 0;
  int relocalised_at = -1;  // frame index, -1: never
  int frames_held = 0, published_while_awaiting = 0;
  double max_p_err = 0, max_rot_err = 0;  // over the frames after relocalisation [m], [rad]
};

// Session 2: loads the map and starts `start` (truth, in the map frame)
// away from session 1's start, with no hint (the filter starts at identity).
Session comeBack(const std::string& path, const sim::World& scene, const sim::StereoRig& rig, const PoseState& start,
                 std::mt19937& rng) {
  const EskfSettings s = filterSettings(1000);
  Eskf f(s, makeCpuBackend(s.max_landmarks, 32));
  EXPECT_EQ(f.reset(PoseState(), 0.0), Status::kOk);
  map_file::MapData map;
  const map_file::MapCalibration running = rigCalibration(rig);
  map_file::MapExpectation expect;
  expect.descriptor_type = map_file::kDescriptorOrb;
  expect.calibration = &running;
  const map_file::MapError err = map_file::readMapFile(path, expect, &map);
  EXPECT_FALSE(err) << err.message;
  Session r;
  r.loaded = static_cast<int>(map.landmarks.size());
  EXPECT_EQ(f.loadMap(map_file::toPriorLandmarks(map)), Status::kOk);
  EXPECT_TRUE(f.awaitingMap());
  PoseState truth = start;
  for (int k = 1; k <= 30; ++k) {
    truth = predictPose(truth, 0.1, s);
    IterationReport rep;
    EXPECT_EQ(f.processFrame(sim::makeFrame(scene, truth, rig, 0.1 * k, 4, rng), &rep), Status::kOk);
    if (rep.relocalising) {
      ++r.frames_held;
      EXPECT_EQ(rep.n_added, 0);
      EXPECT_EQ(f.numLandmarks(), r.loaded);
      continue;
    }
    if (f.awaitingMap()) ++r.published_while_awaiting;
    if (rep.relocalised) r.relocalised_at = k;
    if (r.relocalised_at < 0) continue;
    const auto e = sim::poseError(truth, f.pose());
    r.max_p_err = std::max(r.max_p_err, e.head<3>().norm());
    r.max_rot_err = std::max(r.max_rot_err, e.tail<3>().norm());
  }
  r.landmarks_at_end = f.numLandmarks();
  return r;
}

TEST(MapRelocalise, SavedMapLoadedAndRelocalisedWithoutAHint) {
  std::mt19937 rng(5);
  const sim::StereoRig rig;
  const sim::World scene = sim::randomWorld(rng, 800, Vec3(-4, -2, 3), Vec3(6, 2, 9));
  const std::string path = mapScene(scene, rig, rng);
  // Back 30 cm to the side and 10 cm closer, turned 0.4 rad about the
  // vertical and 0.1 rad about the optical axis, moving the other way.
  PoseState start;
  start.p = Vec3(0.5, 0.3, 0.1);
  start.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Vec3::UnitY()) * Eigen::AngleAxisd(0.1, Vec3::UnitZ()));
  start.v = Vec3(-0.15, 0.0, 0.0);
  const Session r = comeBack(path, scene, rig, start, rng);
  std::printf("session 2: %d landmarks loaded, relocalised at frame %d after %d held, %d at the end; max error "
              "after relocalisation %.2f mm %.3f deg\n",
              r.loaded, r.relocalised_at, r.frames_held, r.landmarks_at_end, 1e3 * r.max_p_err,
              r.max_rot_err * 180 / M_PI);
  EXPECT_GT(r.loaded, 200);
  EXPECT_EQ(r.relocalised_at, 1);  // the first frame sees the mapped scene
  EXPECT_EQ(r.published_while_awaiting, 0);
  EXPECT_LT(r.max_p_err, 0.02);
  EXPECT_LT(r.max_rot_err, 0.01);
  EXPECT_GT(r.landmarks_at_end, r.loaded);  // tracking added landmarks beyond the map
  std::remove(path.c_str());
}

TEST(MapRelocalise, AnotherSceneNeverRelocalises) {
  std::mt19937 rng(6);
  const sim::StereoRig rig;
  const sim::World scene = sim::randomWorld(rng, 800, Vec3(-4, -2, 3), Vec3(6, 2, 9));
  const sim::World other = sim::randomWorld(rng, 800, Vec3(-4, -2, 3), Vec3(6, 2, 9));
  const std::string path = mapScene(scene, rig, rng);
  PoseState start;
  start.v = Vec3(0.2, 0.0, 0.0);
  const Session r = comeBack(path, other, rig, start, rng);
  std::printf("unmapped scene: relocalised at frame %d, %d of 30 frames held\n", r.relocalised_at, r.frames_held);
  EXPECT_EQ(r.relocalised_at, -1);
  EXPECT_EQ(r.frames_held, 30);
  EXPECT_EQ(r.landmarks_at_end, r.loaded);
  std::remove(path.c_str());
}

// A skin-like plane scanned 40 cm along x with a pool of 150: the area
// where session 1 began left the pool long before the save, so the saved
// landmarks cannot place a camera there; the saved keyframes can, and the
// placing keyframe's points tie the pose to the map frame.
struct PlaneScan {
  test::KeyframeScene scene = test::makeKeyframeScene(3000, 0.8, 3);
  std::mt19937 g{9};
  map_file::MapData map;
  PlaneScan() {
    EskfSettings s = filterSettings(150);
    Eskf f(s, makeCpuBackend(s.max_landmarks, 32));
    PoseState start = poseOf(test::cameraAbove(-0.2, 0.0, 0.25, 0.0));
    start.v = Vec3(0.05, 0.0, 0.0);  // camera x is the plane's x
    EXPECT_EQ(f.reset(start, 0.0), Status::kOk);
    KeyframeRecorder rec;
    for (int k = 1; k <= 80; ++k) {
      const StereoFrame frame = test::viewOf(scene, test::cameraAbove(-0.2 + 0.005 * k, 0.0, 0.25, 0.0), g, 16, 0.1 * k);
      EXPECT_EQ(f.processFrame(frame), Status::kOk);
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.linear() = f.pose().q.toRotationMatrix();
      T.translation() = f.pose().p;
      rec.offer(frame, T, [&f] { return f.cameraPoseCovariance(); });
    }
    int skipped = 0;
    map.landmarks = map_file::toMapLandmarks(f.landmarks(), f.landmarkDescriptors(), 32, &skipped);
    map.keyframes = rec.keyframes(Eigen::Isometry3d::Identity());
  }
  static PoseState poseOf(const Eigen::Isometry3d& T) {
    PoseState p;
    p.p = T.translation();
    p.q = Eigen::Quaterniond(T.linear());
    return p;
  }
};

struct PlaneComeBack {
  int relocalised_at = -1, keyframe_fits = 0, landmarks_after_fit = 0;
  double first_p_err = 0, first_rot_err = 0;  // at the relocalising frame [m], [rad]
  double max_p_err = 0, max_rot_err = 0;      // over the frames from it on
};

// Session 2 from near session 1's start, turned 0.3 rad, creeping 1 cm/s.
PlaneComeBack planeComeBack(PlaneScan& scan, bool with_keyframes) {
  const EskfSettings s = filterSettings(1000);
  Eskf f(s, makeCpuBackend(s.max_landmarks, 32));
  EXPECT_EQ(f.reset(PoseState(), 0.0), Status::kOk);
  const std::vector<PriorLandmark> landmarks = map_file::toPriorLandmarks(scan.map);
  EXPECT_EQ(f.loadMap(landmarks, Vec3::Zero(), with_keyframes ? scan.map.keyframes : std::vector<Keyframe>()),
            Status::kOk);
  PlaneComeBack r;
  for (int k = 1; k <= 10; ++k) {
    const Eigen::Isometry3d T = test::cameraAbove(-0.19 + 0.001 * k, 0.01, 0.25, 0.3);
    IterationReport rep;
    EXPECT_EQ(f.processFrame(test::viewOf(scan.scene, T, scan.g, 16, 0.1 * k), &rep), Status::kOk);
    r.keyframe_fits += rep.keyframe_fit;
    if (rep.relocalised) {
      r.relocalised_at = k;
      r.landmarks_after_fit = f.numLandmarks();
    }
    if (r.relocalised_at < 0) continue;
    const auto e = sim::poseError(PlaneScan::poseOf(T), f.pose());
    if (k == r.relocalised_at) {
      r.first_p_err = e.head<3>().norm();
      r.first_rot_err = e.tail<3>().norm();
    }
    r.max_p_err = std::max(r.max_p_err, e.head<3>().norm());
    r.max_rot_err = std::max(r.max_rot_err, e.tail<3>().norm());
  }
  return r;
}

TEST(MapRelocalise, KeyframesPlaceTheCameraWhereTheSavedPoolHasNoLandmarks) {
  PlaneScan scan;
  std::printf("session 1: %zu landmarks, %zu keyframes saved\n", scan.map.landmarks.size(), scan.map.keyframes.size());
  ASSERT_GE(scan.map.keyframes.size(), 15u);  // one per 2 cm of the 40 cm
  // Without the keyframes the saved landmarks never place the camera.
  const PlaneComeBack landmarks_only = planeComeBack(scan, false);
  EXPECT_EQ(landmarks_only.relocalised_at, -1);
  // With them, the second frame is placed on a keyframe: the first frame's
  // placement counts once the second's agrees with it (kKeyframeConfirm*).
  const PlaneComeBack r = planeComeBack(scan, true);
  std::printf("with keyframes: relocalised at frame %d, pool %d -> %d, error there %.2f mm %.3f deg, max %.2f mm "
              "%.3f deg\n",
              r.relocalised_at, static_cast<int>(scan.map.landmarks.size()), r.landmarks_after_fit,
              1e3 * r.first_p_err, r.first_rot_err * 180 / M_PI, 1e3 * r.max_p_err, r.max_rot_err * 180 / M_PI);
  EXPECT_EQ(r.relocalised_at, 2);
  EXPECT_EQ(r.keyframe_fits, 1);
  EXPECT_GT(r.landmarks_after_fit, static_cast<int>(scan.map.landmarks.size()));
  // At the placing frame the keyframe's fit; over the next frames the
  // filter tracks a plane seen at 25 cm, which wanders by millimetres and a
  // degree or two in tilt whatever placed it (its landmarks placing a camera
  // at the scan's end: up to 3.6 mm and 1.2 deg over 10 frames; this test
  // gave 5.5 mm / 1.4 deg in the catkin build and 9.8 mm / 2.4 deg in the
  // sanitizer build). A fit to the wrong keyframe or wrong matches is off by
  // centimetres and tens of degrees.
  EXPECT_LT(r.first_p_err, 3e-3);
  EXPECT_LT(r.first_rot_err, 0.6 * M_PI / 180);
  EXPECT_LT(r.max_p_err, 0.02);
  EXPECT_LT(r.max_rot_err, 4.0 * M_PI / 180);
}

TEST(MapRelocalise, AKeyframeOfAnotherDescriptorLengthRefusesTheWholeMap) {
  PlaneScan scan;
  const EskfSettings s = filterSettings(1000);
  Eskf f(s, makeCpuBackend(s.max_landmarks, 32));
  ASSERT_EQ(f.reset(PoseState(), 0.0), Status::kOk);
  std::vector<Keyframe> keyframes = scan.map.keyframes;
  keyframes.back().descriptor_length = 16;
  keyframes.back().descriptors.resize(keyframes.back().size() * 16);
  EXPECT_EQ(f.loadMap(map_file::toPriorLandmarks(scan.map), Vec3::Zero(), keyframes), Status::kInvalidArgument);
  EXPECT_EQ(f.numLandmarks(), 0);
  EXPECT_EQ(f.mapKeyframes(), 0u);
  EXPECT_FALSE(f.awaitingMap());
  EXPECT_EQ(f.loadMap(map_file::toPriorLandmarks(scan.map), Vec3::Zero(), scan.map.keyframes), Status::kOk);
  EXPECT_EQ(f.mapKeyframes(), scan.map.keyframes.size());
}

TEST(MapRelocalise, LoadRefusedUnlessFreshlyReset) {
  const EskfSettings s = filterSettings(400);
  Eskf f(s, makeCpuBackend(s.max_landmarks, 32));
  ASSERT_EQ(f.reset(PoseState(), 0.0), Status::kOk);
  PriorLandmark l;
  l.covariance = 1e-6 * Mat3::Identity();
  l.descriptor.assign(31, 0);
  EXPECT_EQ(f.loadMap({l}), Status::kInvalidArgument);  // descriptor length
  l.descriptor.assign(32, 0);
  EXPECT_EQ(f.loadMap(std::vector<PriorLandmark>(s.max_landmarks, l)), Status::kCapacityExceeded);
  l.covariance(2, 2) = -1.0;
  EXPECT_EQ(f.loadMap({l}), Status::kNotPositiveDefinite);
  EXPECT_EQ(f.numLandmarks(), 0);
  EXPECT_FALSE(f.awaitingMap());
  l.covariance = 1e-6 * Mat3::Identity();
  EXPECT_EQ(f.loadMap({l}), Status::kOk);
  EXPECT_EQ(f.loadMap({l}), Status::kInvalidArgument);  // the pool is no longer empty
}

// The inertial model (IMU at 200 Hz, frames at 10 Hz): session 1 maps while
// the body moves (inertial_scenario.hpp) and saves its pool with gravity;
// session 2 runs the same motion with the body turned 0.35 rad about the
// vertical and moved 10 cm, loads the map before its gravity alignment,
// and is placed in the map frame by the first frame after it, its tilt
// agreeing with the IMU's, its gravity the map's. The map is saved in a
// frame tilted against gravity (a published frame T_out_world), so a
// session that ignored the map's gravity could not agree with it.
struct InertialSession {
  int relocalised_at = -1, held = 0, published_while_awaiting = 0;
  double max_p_err = 0, max_rot_err = 0, gravity_err = 0;  // after relocalisation [m], [rad], [rad]
};

InertialSession inertialSession(const sim::World& scene, const Eigen::Isometry3d& move, double duration,
                                const Eigen::Isometry3d& T_map_world, const map_file::MapData* load,
                                map_file::MapData* save, std::mt19937& rng) {
  EskfSettings s = testing_settings::inertialTrajectoryFilter();
  s.max_landmarks = 600;
  const CameraExtrinsic e = sim::forwardCamera();
  const sim::InertialTrajectory traj;
  const sim::ImuNoiseModel noise;
  Eskf f(s, makeCpuBackend(s.max_landmarks, 32, poseDim(s)), e);
  EXPECT_EQ(f.reset(PoseState(), 0.0), Status::kOk);
  if (load) EXPECT_EQ(f.loadMap(map_file::toPriorLandmarks(*load), load->gravity_direction), Status::kOk);
  // The map frame: session 1's gravity-aligned world, at its first camera
  // position (the body starts level, so its yaw is the truth's).
  const Vec3 origin = sim::cameraOf(traj.at(0.0), e).p;
  InertialSession r;
  int k_imu = 1;
  for (int k = 1; k * 0.1 <= duration + 1e-9; ++k) {
    const double t = k * 0.1;
    // The IMU reads the same in the turned body: a turn about gravity.
    for (const ImuSample& m : sim::imuSamplesUpTo(traj, noise, t, &k_imu, rng)) EXPECT_EQ(f.addImu(m), Status::kOk);
    PoseState cam = sim::cameraOf(traj.at(t), e);
    cam.p = move * cam.p;
    cam.q = Eigen::Quaterniond(move.linear()) * cam.q;
    IterationReport rep;
    const Status st = f.processFrame(sim::makeFrame(scene, cam, sim::StereoRig(), t, 4, rng), &rep);
    if (st == Status::kAwaitingImu) continue;
    EXPECT_EQ(st, Status::kOk) << toString(st) << " at " << t;
    cam.p = T_map_world * (cam.p - origin);
    cam.q = Eigen::Quaterniond(T_map_world.linear()) * cam.q;
    if (rep.relocalising) {
      ++r.held;
      continue;
    }
    if (load && f.awaitingMap()) ++r.published_while_awaiting;
    if (rep.relocalised) r.relocalised_at = k;
    if (load && r.relocalised_at < 0) continue;
    // Session 1 runs in its own world (T_map_world applies to the saved map only).
    const PoseState est = f.pose();
    const Vec3 p = load ? est.p : Vec3(T_map_world * est.p);
    const Eigen::Quaterniond q = load ? est.q : Eigen::Quaterniond(T_map_world.linear()) * est.q;
    const Vec3 g = load ? f.state().g : Vec3(T_map_world.linear() * f.state().g);
    r.max_p_err = std::max(r.max_p_err, (p - cam.p).norm());
    r.max_rot_err = std::max(r.max_rot_err, q.angularDistance(cam.q));
    const Vec3 down = T_map_world.linear() * Vec3(0, 0, -1);
    r.gravity_err = std::acos(std::min(1.0, g.normalized().dot(down)));
  }
  int skipped = 0;
  if (save) EXPECT_FALSE(map_file::mapFromBackend(f, T_map_world, map_file::MapData(), save, &skipped));
  return r;
}

TEST(MapRelocalise, InertialModelLoadsTheMapAtItsAlignmentAndRelocalisesConsistentlyWithGravity) {
  std::mt19937 rng(7);
  const sim::World scene = sim::randomWorld(rng, 6000, Vec3(-20, -20, -20), Vec3(20, 20, 20));
  Eigen::Isometry3d T_map_world = Eigen::Isometry3d::Identity();
  T_map_world.linear() = Eigen::AngleAxisd(0.4, Vec3::UnitX()).toRotationMatrix();
  T_map_world.translation() = Vec3(0.2, -0.1, 0.05);
  const Vec3 down = T_map_world.linear() * Vec3(0, 0, -1);
  map_file::MapData map;
  const InertialSession s1 =
      inertialSession(scene, Eigen::Isometry3d::Identity(), 3.0, T_map_world, nullptr, &map, rng);
  std::printf("inertial session 1: %zu landmarks saved, max error %.2f mm %.3f deg, gravity (%.4f %.4f %.4f)\n",
              map.landmarks.size(), 1e3 * s1.max_p_err, s1.max_rot_err * 180 / M_PI, map.gravity_direction.x(),
              map.gravity_direction.y(), map.gravity_direction.z());
  ASSERT_GT(map.landmarks.size(), 100u);
  EXPECT_LT(std::acos(map.gravity_direction.dot(down)), 0.02);
  Eigen::Isometry3d move = Eigen::Isometry3d::Identity();
  move.linear() = Eigen::AngleAxisd(0.35, Vec3::UnitZ()).toRotationMatrix();
  move.translation() = Vec3(0.06, -0.08, 0.02);
  const InertialSession s2 = inertialSession(scene, move, 3.0, T_map_world, &map, nullptr, rng);
  std::printf("inertial session 2: relocalised at frame %d after %d held; max error after it %.2f mm %.3f deg, "
              "gravity off the map's down by %.3f deg\n",
              s2.relocalised_at, s2.held, 1e3 * s2.max_p_err, s2.max_rot_err * 180 / M_PI,
              s2.gravity_err * 180 / M_PI);
  EXPECT_GE(s2.relocalised_at, 1);
  EXPECT_LE(s2.held, 2);
  EXPECT_EQ(s2.published_while_awaiting, 0);
  EXPECT_LT(s2.max_p_err, 0.02);
  EXPECT_LT(s2.max_rot_err, 0.01);
  EXPECT_LT(s2.gravity_err, 0.02);
}

TEST(MapRelocalise, InertialLoadNeedsGravityAndAFilterAwaitingItsAlignment) {
  EskfSettings s = testing_settings::inertialTrajectoryFilter();
  Eskf f(s, makeCpuBackend(s.max_landmarks, 32, poseDim(s)), sim::forwardCamera());
  ASSERT_EQ(f.reset(PoseState(), 0.0), Status::kOk);
  PriorLandmark l;
  l.covariance = 1e-6 * Mat3::Identity();
  l.descriptor.assign(32, 0);
  EXPECT_EQ(f.loadMap({l}), Status::kInvalidArgument);  // no gravity direction
  EXPECT_FALSE(f.awaitingMap());
  EXPECT_EQ(f.loadMap({l}, Vec3(0, 0, -1)), Status::kOk);
  EXPECT_TRUE(f.awaitingMap());
  EXPECT_EQ(f.numLandmarks(), 0);  // kept until the alignment
  EXPECT_EQ(f.loadMap({l}, Vec3(0, 0, -1)), Status::kInvalidArgument);  // one map per reset
  std::mt19937 rng(3);
  const sim::InertialTrajectory still;
  for (int k = 1; f.awaitingAlignment(); ++k)
    ASSERT_EQ(f.addImu(sim::imuSample(still, sim::ImuNoiseModel(), 0.005 * k, 0.005, rng)), Status::kOk);
  EXPECT_EQ(f.numLandmarks(), 1);
  EXPECT_TRUE(f.awaitingMap());
  ASSERT_EQ(f.reset(PoseState(), 0.0), Status::kOk);
  EXPECT_FALSE(f.awaitingMap());  // a reset drops a map not applied yet
}

}  // namespace
}  // namespace hapi_eskf
