// Tests of make_globe_bag (the embedded default data set) through its bag:
// determinism, topics/types/counts/rates, calibration round trip, ground-truth
// and IMU consistency, and the geometric check of the renderer: a known sphere
// point projected with the bag's CameraInfo and ground-truth pose lands on the
// rendered texture position (sub-pixel, measured by Lucas-Kanade alignment of
// the image against a prediction built from the bag's own calibration).
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <std_msgs/String.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "bag_contents.hpp"
#include "hapi_sim/globe_sim.hpp"

#ifndef MAKE_GLOBE_BAG
#error "MAKE_GLOBE_BAG (path of the generator) must be defined by the build"
#endif

using namespace hapi_sim;

namespace {

constexpr double kDuration = 1.5;  // 15 stereo frames, 150 IMU samples
constexpr int kFrames = 15;
constexpr int kImu = 150;

std::string tmpPath(const std::string& name) {
  return "/tmp/hapi_sim_bag_test_" + std::to_string(::getpid()) + "_" + name + ".bag";
}

void generate(const std::string& out, int seed, const std::string& extra = "") {
  std::ostringstream cmd;
  cmd << MAKE_GLOBE_BAG << " --output " << out << " --seed " << seed << " --duration " << kDuration
      << " --rate 10 --imu 1 " << extra << " 2>/dev/null";
  ASSERT_EQ(std::system(cmd.str().c_str()), 0) << cmd.str();
}

uint64_t fnv1a(const uint8_t* d, size_t n, uint64_t h = 1469598103934665603ull) {
  for (size_t i = 0; i < n; ++i) { h ^= d[i]; h *= 1099511628211ull; }
  return h;
}

uint64_t fileHash(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::vector<uint8_t> buf((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_GT(buf.size(), 1000u);
  return fnv1a(buf.data(), buf.size());
}

// Hash of every message in bag order: topic, receive time, serialised payload.
uint64_t payloadHash(const std::string& path) {
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  rosbag::View view(bag);
  uint64_t h = 1469598103934665603ull;
  std::vector<uint8_t> buf;
  for (const rosbag::MessageInstance& m : view) {
    const std::string t = m.getTopic();
    h = fnv1a(reinterpret_cast<const uint8_t*>(t.data()), t.size(), h);
    const uint64_t ns = m.getTime().toNSec();
    h = fnv1a(reinterpret_cast<const uint8_t*>(&ns), sizeof ns, h);
    buf.resize(m.size());
    ros::serialization::OStream s(buf.data(), static_cast<uint32_t>(buf.size()));
    m.write(s);
    h = fnv1a(buf.data(), buf.size(), h);
  }
  return h;
}

// Everything the geometric tests need, read back from one bag.
struct BagData : hapi_sim_test::BagTopics {
  std::vector<sensor_msgs::Image> left, right;
  std::vector<sensor_msgs::CameraInfo> info_l, info_r;
  std::vector<geometry_msgs::PoseStamped> gt;
  std::vector<tf2_msgs::TFMessage> tf, tf_static;
  std::vector<sensor_msgs::Imu> imu;
  std::vector<std::string> globe;
};

BagData readBag(const std::string& path) {
  using hapi_sim_test::readMessages;
  BagData d;
  static_cast<hapi_sim_test::BagTopics&>(d) = hapi_sim_test::readBagTopics(path);
  d.left = readMessages<sensor_msgs::Image>(path, "/stereo/left/image_raw");
  d.right = readMessages<sensor_msgs::Image>(path, "/stereo/right/image_raw");
  d.info_l = readMessages<sensor_msgs::CameraInfo>(path, "/stereo/left/camera_info");
  d.info_r = readMessages<sensor_msgs::CameraInfo>(path, "/stereo/right/camera_info");
  d.gt = readMessages<geometry_msgs::PoseStamped>(path, "/ground_truth/pose");
  d.tf = readMessages<tf2_msgs::TFMessage>(path, "/tf");
  d.tf_static = readMessages<tf2_msgs::TFMessage>(path, "/tf_static");
  d.imu = readMessages<sensor_msgs::Imu>(path, "/imu/data");
  for (const std_msgs::String& m : readMessages<std_msgs::String>(path, "/globe/info")) d.globe.push_back(m.data);
  return d;
}

CameraModel cameraFromInfo(const sensor_msgs::CameraInfo& ci) {
  CameraModel c;
  c.width = static_cast<int>(ci.width);
  c.height = static_cast<int>(ci.height);
  c.fx = ci.K[0]; c.fy = ci.K[4]; c.cx = ci.K[2]; c.cy = ci.K[5];
  c.k1 = ci.D.at(0); c.k2 = ci.D.at(1); c.p1 = ci.D.at(2); c.p2 = ci.D.at(3); c.k3 = ci.D.at(4);
  return c;
}

Pose poseFromMsg(const geometry_msgs::Pose& p) {
  Pose P;
  P.p = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  P.q = Eigen::Quaterniond(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z);
  return P;
}

Pose poseFromTf(const geometry_msgs::Transform& t) {
  Pose P;
  P.p = Eigen::Vector3d(t.translation.x, t.translation.y, t.translation.z);
  P.q = Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z);
  return P;
}

Pose compose(const Pose& a, const Pose& b) {  // a * b
  Pose r;
  r.q = a.q * b.q;
  r.p = a.p + a.q * b.p;
  return r;
}

// The globe as the bag describes it (/globe/info YAML: radius, centre, texture).
GlobeScene sceneFromInfo(const std::string& yaml) {
  double radius = 0, cx = 0, cy = 0, cz = 0;
  std::string texture;
  std::istringstream in(yaml);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("radius:", 0) == 0) radius = std::stod(line.substr(7));
    else if (line.rfind("centre:", 0) == 0)
      EXPECT_EQ(std::sscanf(line.c_str(), "centre: [%lf, %lf, %lf]", &cx, &cy, &cz), 3) << line;
    else if (line.rfind("texture:", 0) == 0) {
      const size_t a = line.find('"'), b = line.rfind('"');
      if (a != std::string::npos && b > a) texture = line.substr(a + 1, b - a - 1);
    }
  }
  EXPECT_GT(radius, 0.0);
  return GlobeScene::makeDefault(texture == "generated" ? "" : texture, radius, Eigen::Vector3d(cx, cy, cz));
}

class BagTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    path_a_ = tmpPath("a");
    path_a2_ = tmpPath("a2");
    path_b_ = tmpPath("b");
    generate(path_a_, 1);
    generate(path_a2_, 1);
    generate(path_b_, 2);
    data_ = new BagData(readBag(path_a_));
  }
  static void TearDownTestSuite() {
    std::remove(path_a_.c_str());
    std::remove(path_a2_.c_str());
    std::remove(path_b_.c_str());
    delete data_;
  }
  static std::string path_a_, path_a2_, path_b_;
  static BagData* data_;
};
std::string BagTest::path_a_, BagTest::path_a2_, BagTest::path_b_;
BagData* BagTest::data_ = nullptr;

TEST_F(BagTest, SameSeedIdenticalBagDifferentSeedDifferent) {
  // rosbag's writer stores no wall-clock time: the whole file is reproducible.
  EXPECT_EQ(fileHash(path_a_), fileHash(path_a2_));
  EXPECT_NE(fileHash(path_a_), fileHash(path_b_));
  EXPECT_EQ(payloadHash(path_a_), payloadHash(path_a2_));
  EXPECT_NE(payloadHash(path_a_), payloadHash(path_b_));
}

TEST_F(BagTest, TopicsTypesCountsAndRates) {
  const BagData& d = *data_;
  const std::map<std::string, std::string> want = {
      {"/stereo/left/image_raw", "sensor_msgs/Image"},       {"/stereo/right/image_raw", "sensor_msgs/Image"},
      {"/stereo/left/camera_info", "sensor_msgs/CameraInfo"}, {"/stereo/right/camera_info", "sensor_msgs/CameraInfo"},
      {"/ground_truth/pose", "geometry_msgs/PoseStamped"},    {"/tf", "tf2_msgs/TFMessage"},
      {"/tf_static", "tf2_msgs/TFMessage"},                   {"/imu/data", "sensor_msgs/Imu"},
      {"/globe/info", "std_msgs/String"}};
  for (const auto& kv : want) {
    ASSERT_TRUE(d.types.count(kv.first)) << "missing topic " << kv.first;
    EXPECT_EQ(d.types.at(kv.first), kv.second) << kv.first;
  }
  EXPECT_EQ(d.types.size(), want.size());
  for (const char* t : {"/stereo/left/image_raw", "/stereo/right/image_raw", "/stereo/left/camera_info",
                        "/stereo/right/camera_info", "/ground_truth/pose", "/tf"})
    EXPECT_EQ(d.counts.at(t), kFrames) << t;
  EXPECT_EQ(d.counts.at("/imu/data"), kImu);
  EXPECT_EQ(d.counts.at("/tf_static"), 1);
  EXPECT_EQ(d.counts.at("/globe/info"), 2);  // 1 Hz
  EXPECT_TRUE(d.latched.at("/tf_static"));
  EXPECT_TRUE(d.latched.at("/globe/info"));

  const ros::Time t0(1000000000, 0);
  for (int k = 0; k < kFrames; ++k) {
    const ros::Time tk = t0 + ros::Duration(0, 100000000 * k);  // exactly 10 Hz
    for (const auto* im : {&d.left[k], &d.right[k]}) {
      EXPECT_EQ(im->header.stamp, tk);
      EXPECT_EQ(im->encoding, "mono8");
      EXPECT_EQ(im->width, 640u);
      EXPECT_EQ(im->height, 480u);
      EXPECT_EQ(im->step, 640u);
      EXPECT_EQ(im->data.size(), 640u * 480u);
    }
    EXPECT_EQ(d.left[k].header.frame_id, "stereo_left_optical_frame");
    EXPECT_EQ(d.right[k].header.frame_id, "stereo_right_optical_frame");
    EXPECT_EQ(d.info_l[k].header.stamp, tk);
    EXPECT_EQ(d.info_r[k].header.stamp, tk);
    EXPECT_EQ(d.info_l[k].header.frame_id, "stereo_left_optical_frame");
    EXPECT_EQ(d.info_r[k].header.frame_id, "stereo_right_optical_frame");
    EXPECT_EQ(d.gt[k].header.stamp, tk);
    EXPECT_EQ(d.gt[k].header.frame_id, "world");
    ASSERT_EQ(d.tf[k].transforms.size(), 1u);
    EXPECT_EQ(d.tf[k].transforms[0].header.frame_id, "world");
    EXPECT_EQ(d.tf[k].transforms[0].child_frame_id, "ground_truth/stereo_left_optical_frame");
    EXPECT_EQ(d.tf[k].transforms[0].header.stamp, tk);
  }
  for (int i = 0; i < kImu; ++i) {
    EXPECT_EQ(d.imu[i].header.stamp, t0 + ros::Duration(0, 10000000 * i));  // exactly 100 Hz
    EXPECT_EQ(d.imu[i].header.frame_id, "imu_link");
    EXPECT_EQ(d.imu[i].orientation_covariance[0], -1.0);
  }
  // Images are textured (the globe fills a good part of the view) and noisy.
  double m = 0, m2 = 0;
  for (uint8_t v : d.left[0].data) { m += v; m2 += double(v) * v; }
  m /= d.left[0].data.size();
  EXPECT_GT(std::sqrt(m2 / d.left[0].data.size() - m * m), 15.0);
}

TEST_F(BagTest, CameraInfoRoundTripsTheRig) {
  const BagData& d = *data_;
  const StereoRigModel rig = StereoRigModel::makeDefault();
  const CameraInfoData want[2] = {rig.leftInfo(), rig.rightInfo()};
  ASSERT_EQ(d.tf_static.size(), 1u);
  const geometry_msgs::TransformStamped* lr = nullptr;
  const geometry_msgs::TransformStamped* li = nullptr;
  for (const auto& t : d.tf_static[0].transforms) {
    EXPECT_EQ(t.header.frame_id, "stereo_left_optical_frame");
    if (t.child_frame_id == "stereo_right_optical_frame") lr = &t;
    if (t.child_frame_id == "imu_link") li = &t;
  }
  ASSERT_NE(lr, nullptr);
  ASSERT_NE(li, nullptr);
  const double B = lr->transform.translation.x;
  EXPECT_DOUBLE_EQ(B, rig.baseline);
  EXPECT_EQ(lr->transform.translation.y, 0.0);
  EXPECT_EQ(lr->transform.translation.z, 0.0);
  EXPECT_EQ(lr->transform.rotation.w, 1.0);
  EXPECT_EQ(li->transform.translation.x, 0.0);
  EXPECT_EQ(li->transform.rotation.w, 1.0);

  for (int k : {0, kFrames - 1}) {
    const sensor_msgs::CameraInfo* got[2] = {&d.info_l[k], &d.info_r[k]};
    for (int c = 0; c < 2; ++c) {
      EXPECT_EQ(got[c]->width, 640u);
      EXPECT_EQ(got[c]->height, 480u);
      EXPECT_EQ(got[c]->distortion_model, "plumb_bob");
      ASSERT_EQ(got[c]->D.size(), 5u);
      for (int i = 0; i < 5; ++i) EXPECT_EQ(got[c]->D[i], want[c].D[i]);
      for (int i = 0; i < 9; ++i) EXPECT_EQ(got[c]->K[i], want[c].K[i]);
      for (int i = 0; i < 9; ++i) EXPECT_EQ(got[c]->R[i], (i % 4 == 0) ? 1.0 : 0.0);  // parallel rig
      for (int i = 0; i < 12; ++i) EXPECT_EQ(got[c]->P[i], want[c].P[i]);
    }
    // Mild, non-zero lens distortion.
    EXPECT_GT(std::abs(got[0]->D[0]), 1e-3);
    EXPECT_LT(std::abs(got[0]->D[0]), 0.2);
    // ROS stereo convention: P_right[3] = -fx' * baseline, consistent with tf_static.
    EXPECT_EQ(got[0]->P[3], 0.0);
    EXPECT_NEAR(-got[1]->P[3] / got[1]->P[0], B, 1e-12);
  }
}

TEST_F(BagTest, GroundTruthPoseTfAndTrajectoryAgree) {
  const BagData& d = *data_;
  ASSERT_FALSE(d.globe.empty());
  const GlobeScene scene = sceneFromInfo(d.globe[0]);
  EXPECT_NE(scene.texture_source, "");
  const Trajectory traj(scene);
  for (int k = 0; k < kFrames; ++k) {
    const Pose a = poseFromMsg(d.gt[k].pose), b = poseFromTf(d.tf[k].transforms[0].transform);
    const Pose c = traj.pose(0.1 * k);
    EXPECT_LT((a.p - b.p).norm(), 1e-12);
    EXPECT_LT(a.q.angularDistance(b.q), 1e-9);
    EXPECT_LT((a.p - c.p).norm(), 1e-12);
    EXPECT_LT(a.q.angularDistance(c.q), 1e-9);
    // The camera looks at the globe: its centre is in front, within the field of view.
    const Eigen::Vector3d cc = a.q.conjugate() * (scene.centre - a.p);
    EXPECT_GT(cc.z(), 2 * scene.radius);
    EXPECT_LT(std::hypot(cc.x(), cc.y()) / cc.z(), 0.4);
  }
}

// IMU in imu_link (= left optical frame): gyro = body angular rate, accel =
// specific force R^T (a - g). Checked against finite differences of the
// bag's own ground-truth poses, so a frame, sign or gravity error fails.
TEST_F(BagTest, ImuConsistentWithGroundTruth) {
  const BagData& d = *data_;
  const double dt = 0.1;
  double gyro_sq = 0;
  int n_gyro = 0;
  for (int k = 0; 10 * k + 10 < kImu && k + 1 < kFrames; ++k) {
    const Pose a = poseFromMsg(d.gt[k].pose), b = poseFromMsg(d.gt[k + 1].pose);
    const Eigen::AngleAxisd aa(a.q.conjugate() * b.q);
    const Eigen::Vector3d w_gt = aa.axis() * aa.angle() / dt;  // mean body rate over the interval
    Eigen::Vector3d w_imu = Eigen::Vector3d::Zero();
    for (int i = 10 * k; i <= 10 * k + 10; ++i) {  // trapezoid over the same interval
      const double wgt = (i == 10 * k || i == 10 * k + 10) ? 0.5 : 1.0;
      w_imu += wgt * Eigen::Vector3d(d.imu[i].angular_velocity.x, d.imu[i].angular_velocity.y,
                                     d.imu[i].angular_velocity.z);
    }
    w_imu /= 10.0;
    EXPECT_LT((w_imu - w_gt).norm(), 0.02) << "frame " << k;
    gyro_sq += (w_imu - w_gt).squaredNorm();
    ++n_gyro;
  }
  ASSERT_GT(n_gyro, 10);
  EXPECT_LT(std::sqrt(gyro_sq / n_gyro), 0.01);
  // The camera really rotates, so the check above is not vacuous.
  const Pose first = poseFromMsg(d.gt.front().pose), last = poseFromMsg(d.gt.back().pose);
  EXPECT_GT(first.q.angularDistance(last.q), 0.02);

  for (int k = 1; k + 1 < kFrames; ++k) {
    const Pose pm = poseFromMsg(d.gt[k - 1].pose), p0 = poseFromMsg(d.gt[k].pose), pp = poseFromMsg(d.gt[k + 1].pose);
    const Eigen::Vector3d a_w = (pp.p - 2 * p0.p + pm.p) / (dt * dt);
    const sensor_msgs::Imu& m = d.imu[10 * k];  // same stamp as frame k
    ASSERT_EQ(m.header.stamp, d.gt[k].header.stamp);
    const Eigen::Vector3d f(m.linear_acceleration.x, m.linear_acceleration.y, m.linear_acceleration.z);
    const Eigen::Vector3d g_est = p0.q * f - a_w;  // = -g = (0, 0, 9.81)
    EXPECT_LT((g_est - Eigen::Vector3d(0, 0, 9.81)).norm(), 0.15) << "frame " << k;
  }
}

// ------------------------------------------------------------ geometry
struct PatchResult {
  Eigen::Vector2d shift;  // where the texture really is, minus the projection
  double rms;             // photometric residual after alignment (grey levels)
};

// Predicted intensity at pixel q (+ offset): the renderer's 2x2 supersampled
// box filter, recomputed from the bag's calibration and pose.
bool predict(const GlobeScene& scene, const CameraModel& cam, const Pose& T, const Eigen::Vector2d& q, double* val) {
  double acc = 0;
  for (double sy : {-0.25, 0.25})
    for (double sx : {-0.25, 0.25}) {
      Eigen::Vector3d X;
      if (!castRay(q + Eigen::Vector2d(sx, sy), T, cam, scene, &X)) return false;
      double lat, lon;
      scene.latLonFromPoint(X, &lat, &lon);
      acc += scene.sample(lat, lon);
    }
  *val = acc / 4;
  return true;
}

// Sub-pixel displacement of the image content around the projection p of a
// sphere point, by iterative Lucas-Kanade on a 15x15 window: find s with
// I(q) = E(q + s), E predicted from the bag's model. Returns false for a
// window without enough texture or crossing the limb.
bool alignPatch(const GlobeScene& scene, const CameraModel& cam, const Pose& T, const sensor_msgs::Image& img,
                const Eigen::Vector2d& p, PatchResult* out) {
  const int h = 7;
  const int u0 = static_cast<int>(std::lround(p.x())), v0 = static_cast<int>(std::lround(p.y()));
  if (u0 - h - 2 < 0 || v0 - h - 2 < 0 || u0 + h + 2 >= cam.width || v0 + h + 2 >= cam.height) return false;
  Eigen::Vector2d s = Eigen::Vector2d::Zero();
  double rms = 0;
  for (int it = 0; it < 6; ++it) {
    Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
    Eigen::Vector2d b = Eigen::Vector2d::Zero();
    double r2 = 0;
    int n = 0;
    for (int dv = -h; dv <= h; ++dv)
      for (int du = -h; du <= h; ++du) {
        const Eigen::Vector2d q(u0 + du, v0 + dv);
        double e, ex0, ex1, ey0, ey1;
        if (!predict(scene, cam, T, q + s, &e) || !predict(scene, cam, T, q + s + Eigen::Vector2d(-1, 0), &ex0) ||
            !predict(scene, cam, T, q + s + Eigen::Vector2d(1, 0), &ex1) ||
            !predict(scene, cam, T, q + s + Eigen::Vector2d(0, -1), &ey0) ||
            !predict(scene, cam, T, q + s + Eigen::Vector2d(0, 1), &ey1))
          return false;
        const Eigen::Vector2d g(0.5 * (ex1 - ex0), 0.5 * (ey1 - ey0));
        const double r = img.data[static_cast<size_t>(v0 + dv) * img.step + (u0 + du)] - e;
        A += g * g.transpose();
        b += g * r;
        r2 += r * r;
        ++n;
      }
    // Enough texture in both directions (mean squared gradient >= 4 grey^2/px^2).
    const double min_eig = 0.5 * A.trace() - std::sqrt(0.25 * std::pow(A(0, 0) - A(1, 1), 2) + A(0, 1) * A(0, 1));
    if (min_eig < 4.0 * n) return false;
    const Eigen::Vector2d ds = A.ldlt().solve(b);
    s += ds;
    rms = std::sqrt(r2 / n);
    if (s.norm() > 4.0) return false;  // diverged
    if (ds.norm() < 1e-3) break;
  }
  out->shift = s;
  out->rms = rms;
  return true;
}

// Aligns up to max_patches well-textured patches around projected sphere
// points of a lat/lon grid; returns the per-patch results.
std::vector<PatchResult> alignImage(const GlobeScene& scene, const CameraModel& cam, const Pose& T,
                                    const sensor_msgs::Image& img, int max_patches) {
  std::vector<PatchResult> res;
  for (int ilat = -12; ilat <= 12 && static_cast<int>(res.size()) < max_patches; ++ilat)
    for (int ilon = 0; ilon < 72 && static_cast<int>(res.size()) < max_patches; ++ilon) {
      const Eigen::Vector3d X = scene.pointFromLatLon(ilat * 5.0 * M_PI / 180, ilon * 5.0 * M_PI / 180 - M_PI);
      // Facing the camera (no limb inside the window).
      const Eigen::Vector3d n = (X - scene.centre).normalized();
      if (n.dot((T.p - X).normalized()) < 0.5) continue;
      Eigen::Vector2d px;
      if (!project(X, T, cam, &px)) continue;
      // project/castRay are inverses through the distortion model.
      Eigen::Vector3d Y;
      if (px.x() < 0 || px.y() < 0 || px.x() > cam.width - 1 || px.y() > cam.height - 1) continue;
      EXPECT_TRUE(castRay(px, T, cam, scene, &Y));
      Eigen::Vector2d px2;
      EXPECT_TRUE(project(Y, T, cam, &px2));
      EXPECT_LT((px2 - px).norm(), 1e-6);
      EXPECT_LT((Y - X).norm(), 1e-7);
      PatchResult r;
      if (alignPatch(scene, cam, T, img, px, &r)) res.push_back(r);
    }
  return res;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? NAN : v[v.size() / 2];
}

TEST_F(BagTest, ProjectedSpherePointsLandOnRenderedTexture) {
  const BagData& d = *data_;
  const GlobeScene scene = sceneFromInfo(d.globe.at(0));
  const Pose T_lr = poseFromTf(d.tf_static.at(0).transforms.at(0).transform);
  ASSERT_EQ(d.tf_static[0].transforms[0].child_frame_id, "stereo_right_optical_frame");
  for (int k : {0, 7, kFrames - 1}) {
    const Pose T_wl = poseFromMsg(d.gt[k].pose);
    const Pose T_wr = compose(T_wl, T_lr);
    const CameraModel cams[2] = {cameraFromInfo(d.info_l[k]), cameraFromInfo(d.info_r[k])};
    const Pose poses[2] = {T_wl, T_wr};
    const sensor_msgs::Image* imgs[2] = {&d.left[k], &d.right[k]};
    for (int c = 0; c < 2; ++c) {
      const std::vector<PatchResult> res = alignImage(scene, cams[c], poses[c], *imgs[c], 30);
      ASSERT_GE(res.size(), 10u) << "frame " << k << " camera " << c << ": too few textured patches";
      std::vector<double> err, rms;
      for (const PatchResult& r : res) {
        // Rendered geometry within 0.5 px everywhere.
        EXPECT_LT(r.shift.norm(), 0.5) << "frame " << k << " camera " << c;
        err.push_back(r.shift.norm());
        rms.push_back(r.rms);
      }
      // Only noise (sigma 2 grey levels + quantisation) is left: sub-0.1 px typical
      // error, and the texture value at each point is what the image shows.
      std::printf("frame %2d camera %d: %zu patches, median |shift| %.3f px, max %.3f px, median rms %.2f grey\n", k, c,
                  res.size(), median(err), *std::max_element(err.begin(), err.end()), median(rms));
      EXPECT_LT(median(err), 0.1) << "frame " << k << " camera " << c;
      EXPECT_LT(median(rms), 3.0) << "frame " << k << " camera " << c;
    }
  }
}

// The check above can fail: a 1 px principal-point error or a wrong baseline
// sign is detected with the right magnitude.
TEST_F(BagTest, GeometricCheckDetectsWrongCalibration) {
  const BagData& d = *data_;
  const GlobeScene scene = sceneFromInfo(d.globe.at(0));
  const int k = 7;
  const Pose T_wl = poseFromMsg(d.gt[k].pose);
  CameraModel bad = cameraFromInfo(d.info_l[k]);
  bad.cx += 1.0;
  std::vector<double> sx;
  for (const PatchResult& r : alignImage(scene, bad, T_wl, d.left[k], 20)) sx.push_back(r.shift.x());
  ASSERT_GE(sx.size(), 10u);
  std::printf("cx + 1 px: median shift %.3f px over %zu patches\n", median(sx), sx.size());
  EXPECT_NEAR(median(sx), 1.0, 0.15);  // the content sits 1 px right of the (wrong) projection

  Pose T_lr_flipped;
  T_lr_flipped.p = Eigen::Vector3d(-d.tf_static[0].transforms[0].transform.translation.x, 0, 0);
  const Pose T_wr_bad = compose(T_wl, T_lr_flipped);
  std::vector<PatchResult> res = alignImage(scene, cameraFromInfo(d.info_r[k]), T_wr_bad, d.right[k], 20);
  // Flipped baseline: 2 * f * B / Z ~ 120 px of disparity error; most windows
  // do not even converge, those that do are far off.
  int good = 0;
  for (const PatchResult& r : res) good += r.shift.norm() < 0.5;
  EXPECT_LT(good, 3);
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
