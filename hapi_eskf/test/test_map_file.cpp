// The map file (docs/DESIGN.md "Map file"): an exact round trip, and each
// kind of bad file refused with its own fault, loading nothing.
#include "hapi_eskf/map_file/map_checks.hpp"
#include "hapi_eskf/map_file/map_format.hpp"
#include "hapi_eskf/map_file/map_reader.hpp"
#include "hapi_eskf/map_file/map_writer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <unistd.h>

namespace hapi_eskf {
namespace map_file {
namespace {

MapCalibration camera() {
  MapCalibration c;
  c.width = 752;
  c.height = 480;
  c.fx = 458.654;
  c.fy = 457.296;
  c.cx = 367.215;
  c.cy = 248.375;
  c.baseline = 0.110073;
  c.has_imu = true;
  c.imu_cam.R_imu_cam = Eigen::AngleAxisd(0.02, Vec3(0.3, -1.0, 0.2).normalized()).toRotationMatrix();
  c.imu_cam.p_imu_cam = Vec3(-0.0216, -0.0647, 0.0098);
  return c;
}

// A map of n landmarks with distinct, non-trivial values in every field.
MapData sampleMap(int n) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  MapData m;
  m.map_frame = "map";
  m.camera_frame = "stereo_left_optical_frame";
  m.gravity_direction = Vec3(0.1, 0.98, -0.05).normalized();
  m.created = 1795600000.125;
  m.calibration = camera();
  for (int i = 0; i < n; ++i) {
    MapLandmark l;
    l.id = 1000 + 3 * i;
    l.position = Vec3(g(rng), g(rng), 0.25 + 0.01 * g(rng));
    Eigen::Matrix3d A = Eigen::Matrix3d::NullaryExpr([&] { return 1e-3 * g(rng); });
    const Mat3 S = A * A.transpose() + 1e-8 * Mat3::Identity();
    l.covariance = 0.5 * (S + S.transpose());  // as the filter's read-back (exactly symmetric)
    l.times_observed = 1 + i % 17;
    l.descriptor.resize(32);
    for (auto& b : l.descriptor) b = static_cast<uint8_t>(rng());
    m.landmarks.push_back(l);
  }
  return m;
}

// Keyframes with distinct values in every field (the landmarks' 32-byte descriptors).
void addKeyframes(MapData* m, int n, int points) {
  std::mt19937 rng(9);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int k = 0; k < n; ++k) {
    Keyframe kf;
    kf.id = 50 + 7 * k;
    kf.stamp = 1795600000.0 + 0.1 * k;
    kf.T_map_cam.linear() = Eigen::AngleAxisd(0.3 * k + 0.1, Vec3(g(rng), g(rng), g(rng)).normalized()).toRotationMatrix();
    kf.T_map_cam.translation() = Vec3(g(rng), g(rng), g(rng));
    Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::NullaryExpr([&] { return 1e-3 * g(rng); });
    const Mat6 S = A * A.transpose() + 1e-8 * Mat6::Identity();
    kf.pose_covariance = 0.5 * (S + S.transpose());
    kf.descriptor_length = 32;
    for (int i = 0; i < points; ++i) {
      kf.points.emplace_back(g(rng), g(rng), 0.3 + 0.01 * g(rng));
      Eigen::Matrix3d B = Eigen::Matrix3d::NullaryExpr([&] { return 1e-3 * g(rng); });
      const Mat3 C = B * B.transpose() + 1e-9 * Mat3::Identity();
      kf.point_covariances.push_back(0.5 * (C + C.transpose()));
      for (int b = 0; b < 32; ++b) kf.descriptors.push_back(static_cast<uint8_t>(rng()));
    }
    m->keyframes.push_back(kf);
  }
}

std::vector<uint8_t> encoded(const MapData& m) {
  MapError e;
  std::vector<uint8_t> bytes = encodeMap(m, &e);
  EXPECT_FALSE(e) << e.message;
  return bytes;
}

uint64_t u64At(const std::vector<uint8_t>& b, std::size_t at) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= uint64_t(b[at + i]) << (8 * i);
  return v;
}
void putF64(std::vector<uint8_t>* b, std::size_t at, double v) { std::memcpy(b->data() + at, &v, 8); }
void putU32(std::vector<uint8_t>* b, std::size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) (*b)[at + i] = uint8_t(v >> (8 * i));
}

// Byte offset of section `index` of the table (written in the order meta,
// calibration, landmarks) and of landmark k's record.
std::size_t sectionOffset(const std::vector<uint8_t>& b, int index) {
  return u64At(b, kHeaderBytes + index * kSectionEntryBytes + 8);
}
std::size_t landmarkOffset(const std::vector<uint8_t>& b, int k) {
  return sectionOffset(b, 2) + 1 + 4 + 8 + k * (kLandmarkFixedBytes + 32);
}

// Decodes into a map that already holds something: a refused file must leave it as it was.
MapError decode(const std::vector<uint8_t>& b, const MapExpectation& expect = {}) {
  MapData out = sampleMap(1);
  const MapError e = decodeMap(b.data(), b.size(), expect, &out);
  if (e) {
    EXPECT_EQ(out.landmarks.size(), 1u) << "a refused file changed the output";
    EXPECT_EQ(out.landmarks[0].id, 1000u);
  }
  return e;
}

void expectSame(const MapData& a, const MapData& b) {
  EXPECT_EQ(a.map_frame, b.map_frame);
  EXPECT_EQ(a.camera_frame, b.camera_frame);
  EXPECT_EQ(a.gravity_direction, b.gravity_direction);
  EXPECT_EQ(a.created, b.created);
  EXPECT_EQ(a.calibration.width, b.calibration.width);
  EXPECT_EQ(a.calibration.height, b.calibration.height);
  EXPECT_EQ(a.calibration.fx, b.calibration.fx);
  EXPECT_EQ(a.calibration.fy, b.calibration.fy);
  EXPECT_EQ(a.calibration.cx, b.calibration.cx);
  EXPECT_EQ(a.calibration.cy, b.calibration.cy);
  EXPECT_EQ(a.calibration.baseline, b.calibration.baseline);
  EXPECT_EQ(a.calibration.has_imu, b.calibration.has_imu);
  EXPECT_EQ(a.calibration.imu_cam.R_imu_cam, b.calibration.imu_cam.R_imu_cam);
  EXPECT_EQ(a.calibration.imu_cam.p_imu_cam, b.calibration.imu_cam.p_imu_cam);
  EXPECT_EQ(a.descriptor_type, b.descriptor_type);
  EXPECT_EQ(a.descriptor_length, b.descriptor_length);
  ASSERT_EQ(a.landmarks.size(), b.landmarks.size());
  for (std::size_t i = 0; i < a.landmarks.size(); ++i) {
    EXPECT_EQ(a.landmarks[i].id, b.landmarks[i].id);
    EXPECT_EQ(a.landmarks[i].position, b.landmarks[i].position);  // bit for bit
    EXPECT_EQ(a.landmarks[i].covariance, b.landmarks[i].covariance);
    EXPECT_EQ(a.landmarks[i].times_observed, b.landmarks[i].times_observed);
    EXPECT_EQ(a.landmarks[i].descriptor, b.landmarks[i].descriptor);
  }
  ASSERT_EQ(a.keyframes.size(), b.keyframes.size());
  for (std::size_t k = 0; k < a.keyframes.size(); ++k) {
    const Keyframe &x = a.keyframes[k], &y = b.keyframes[k];
    EXPECT_EQ(x.id, y.id);
    EXPECT_EQ(x.stamp, y.stamp);
    EXPECT_EQ(x.T_map_cam.matrix(), y.T_map_cam.matrix());
    EXPECT_EQ(x.pose_covariance, y.pose_covariance);
    EXPECT_EQ(x.descriptor_length, y.descriptor_length);
    EXPECT_EQ(x.points, y.points);
    EXPECT_EQ(x.point_covariances, y.point_covariances);
    EXPECT_EQ(x.descriptors, y.descriptors);
  }
}

TEST(MapFile, RoundTripIsExact) {
  const MapData m = sampleMap(300);
  const std::vector<uint8_t> b = encoded(m);
  MapData back;
  const MapCalibration running = camera();
  MapExpectation expect;
  expect.descriptor_type = kDescriptorOrb;
  expect.calibration = &running;
  const MapError e = decodeMap(b.data(), b.size(), expect, &back);
  ASSERT_FALSE(e) << e.message;
  expectSame(m, back);
  // The file is its header, table and sections, nothing else.
  EXPECT_EQ(b.size(), sectionOffset(b, 2) + 1 + 4 + 8 + 300 * (kLandmarkFixedBytes + 32));
}

TEST(MapFile, KeyframesRoundTripExactlyAndAreOptional) {
  MapData m = sampleMap(20);
  addKeyframes(&m, 5, 40);
  const std::vector<uint8_t> b = encoded(m);
  MapData back;
  MapError e = decodeMap(b.data(), b.size(), {}, &back);
  ASSERT_FALSE(e) << e.message;
  expectSame(m, back);
  // Written as an optional section (flags 0) after the three required ones.
  EXPECT_EQ(u64At(b, kHeaderBytes + 3 * kSectionEntryBytes) & 0xffffffffu, uint64_t{kSectionKeyframes});
  EXPECT_EQ(u64At(b, kHeaderBytes + 3 * kSectionEntryBytes) >> 32, 0u);
  EXPECT_EQ(b.size(), sectionOffset(b, 3) + 8 + 5 * (kKeyframeFixedBytes + 40 * (kKeyframePointFixedBytes + 32)));
  // Every truncation of the keyframes section is refused.
  for (std::size_t cut = sectionOffset(b, 3); cut < b.size(); cut += 97) {
    std::vector<uint8_t> t(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(cut));
    EXPECT_TRUE(decode(t)) << "cut at " << cut;
  }
}

TEST(MapFile, BadKeyframesAreRefusedByReaderAndWriter) {
  MapData good = sampleMap(3);
  addKeyframes(&good, 2, 5);
  auto refused = [&](const std::function<void(MapData*)>& spoil, MapFault fault) {
    MapData m = good;
    spoil(&m);
    MapError e;
    EXPECT_TRUE(encodeMap(m, &e).empty());
    EXPECT_EQ(e.fault, fault) << e.message;
  };
  refused([](MapData* m) { m->keyframes[1].id = 0; }, MapFault::kBadValue);
  refused([](MapData* m) { m->keyframes[1].id = m->keyframes[0].id; }, MapFault::kBadValue);
  refused([](MapData* m) { m->keyframes[0].T_map_cam.linear() *= 1.01; }, MapFault::kBadValue);
  refused([](MapData* m) { m->keyframes[0].points[2].x() = std::nan(""); }, MapFault::kNotFinite);
  refused([](MapData* m) { m->keyframes[0].pose_covariance(0, 0) = -1.0; }, MapFault::kCovarianceNotPd);
  refused([](MapData* m) { m->keyframes[1].point_covariances[4] = Mat3::Zero(); }, MapFault::kCovarianceNotPd);
  refused([](MapData* m) { m->keyframes[1].descriptors.pop_back(); }, MapFault::kDescriptorType);
  // The reader's own copy of the rules: a NaN written into the first
  // keyframe's first point.
  std::vector<uint8_t> b = encoded(good);
  putF64(&b, sectionOffset(b, 3) + 8 + kKeyframeFixedBytes, std::nan(""));
  EXPECT_EQ(decode(b).fault, MapFault::kNotFinite);
  // A point count larger than the section holds.
  b = encoded(good);
  putU32(&b, sectionOffset(b, 3) + 8 + kKeyframeFixedBytes - 4, 1000000);
  EXPECT_EQ(decode(b).fault, MapFault::kBadSize);
}

TEST(MapFile, ExtremeCovariancesComeBackBitForBit) {
  // Entries near the largest double (the writer's symmetrising once summed
  // them to infinity) and subnormal off-diagonal entries.
  MapData m = sampleMap(2);
  m.landmarks[0].covariance = Mat3::Identity() * 1e308;
  m.landmarks[0].covariance(0, 1) = m.landmarks[0].covariance(1, 0) = 8e307;
  m.landmarks[1].covariance(0, 2) = m.landmarks[1].covariance(2, 0) = 5e-324;
  const std::vector<uint8_t> b = encoded(m);
  MapData back;
  const MapError e = decodeMap(b.data(), b.size(), {}, &back);
  ASSERT_FALSE(e) << e.message;
  expectSame(m, back);
}

TEST(MapFile, FileRoundTripAndAnEmptyMap) {
  const std::string path = ::testing::TempDir() + "map_file_test_" + std::to_string(::getpid()) + ".hmap";
  for (int n : {0, 5}) {
    MapData m = sampleMap(n);
    m.gravity_direction = Vec3::Zero();  // no IMU
    m.calibration.has_imu = false;
    m.calibration.imu_cam = CameraExtrinsic();
    ASSERT_FALSE(writeMapFile(path, m)) << n;
    MapData back;
    const MapError e = readMapFile(path, {}, &back);
    ASSERT_FALSE(e) << e.message;
    expectSame(m, back);
  }
  std::remove(path.c_str());
  MapData back;
  EXPECT_EQ(readMapFile(path, {}, &back).fault, MapFault::kIo);
}

TEST(MapFile, TruncatedAnywhere) {
  const std::vector<uint8_t> b = encoded(sampleMap(4));
  for (std::size_t cut : {std::size_t(0), std::size_t(5), std::size_t(12), std::size_t(30), b.size() / 2,
                          b.size() - 1}) {
    const std::vector<uint8_t> part(b.begin(), b.begin() + cut);
    const MapError e = decode(part);
    EXPECT_EQ(e.fault, MapFault::kTruncated) << "cut at " << cut << ": " << e.message;
  }
}

TEST(MapFile, CorruptMagic) {
  std::vector<uint8_t> b = encoded(sampleMap(2));
  b[3] ^= 0x20;
  EXPECT_EQ(decode(b).fault, MapFault::kMagic);
  const std::string ply = "ply\nformat ascii 1.0\n";
  EXPECT_EQ(decode(std::vector<uint8_t>(ply.begin(), ply.end())).fault, MapFault::kMagic);
}

TEST(MapFile, OtherVersion) {
  std::vector<uint8_t> b = encoded(sampleMap(2));
  putU32(&b, 8, kVersion + 1);
  const MapError e = decode(b);
  EXPECT_EQ(e.fault, MapFault::kVersion);
  EXPECT_NE(e.message.find("version 2"), std::string::npos) << e.message;
}

TEST(MapFile, OtherDescriptorType) {
  const std::vector<uint8_t> b = encoded(sampleMap(2));
  MapExpectation akaze;
  akaze.descriptor_type = kDescriptorAkaze;
  EXPECT_EQ(decode(b, akaze).fault, MapFault::kDescriptorType);
  std::vector<uint8_t> unknown = b;
  unknown[sectionOffset(b, 2)] = 7;
  EXPECT_EQ(decode(unknown).fault, MapFault::kDescriptorType);
  std::vector<uint8_t> wrong_length = b;
  putU32(&wrong_length, sectionOffset(b, 2) + 1, 61);  // AKAZE's length with ORB's type
  EXPECT_EQ(decode(wrong_length).fault, MapFault::kDescriptorType);
}

TEST(MapFile, OtherCamera) {
  const std::vector<uint8_t> b = encoded(sampleMap(2));
  MapExpectation expect;
  MapCalibration other = camera();
  expect.calibration = &other;
  EXPECT_FALSE(decode(b, expect));
  other.fx *= 1.001;  // re-calibration of the same rig
  EXPECT_FALSE(decode(b, expect));
  other.fx *= 1.03;  // another lens
  MapError e = decode(b, expect);
  EXPECT_EQ(e.fault, MapFault::kCalibrationMismatch);
  EXPECT_NE(e.message.find("fx"), std::string::npos) << e.message;
  other = camera();
  other.width = 640;
  EXPECT_EQ(decode(b, expect).fault, MapFault::kCalibrationMismatch);
  other = camera();
  other.baseline = 0.12;
  e = decode(b, expect);
  EXPECT_EQ(e.fault, MapFault::kCalibrationMismatch);
  EXPECT_NE(e.message.find("baseline"), std::string::npos) << e.message;
  other = camera();
  other.imu_cam.p_imu_cam.x() += 0.02;
  EXPECT_EQ(decode(b, expect).fault, MapFault::kCalibrationMismatch);
  other.has_imu = false;  // no IMU now: its extrinsic is not compared
  EXPECT_FALSE(decode(b, expect));
}

TEST(MapFile, NaNAnywhereInANumber) {
  const std::vector<uint8_t> b = encoded(sampleMap(3));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::size_t lm = landmarkOffset(b, 1);
  for (std::size_t at : {lm + 8 + 8,                    // position y
                         lm + 8 + 24 + 8,               // covariance xy (both halves)
                         sectionOffset(b, 1) + 8 + 8,   // calibration fy
                         sectionOffset(b, 1) + 8 + 40 + 1 + 32}) {  // R_imu_cam(1,1)
    std::vector<uint8_t> bad = b;
    putF64(&bad, at, nan);
    const MapError e = decode(bad);
    EXPECT_EQ(e.fault, MapFault::kNotFinite) << "at " << at << ": " << e.message;
  }
  std::vector<uint8_t> bad = b;
  putF64(&bad, lm + 8, std::numeric_limits<double>::infinity());
  const MapError e = decode(bad);
  EXPECT_EQ(e.fault, MapFault::kNotFinite);
  EXPECT_NE(e.message.find("landmark 1 position"), std::string::npos) << e.message;
}

TEST(MapFile, CovarianceNotPositiveDefinite) {
  const std::vector<uint8_t> b = encoded(sampleMap(3));
  const std::size_t cov = landmarkOffset(b, 2) + 8 + 24;  // xx xy xz yy yz zz
  std::vector<uint8_t> negative = b;
  putF64(&negative, cov + 5 * 8, -1e-6);  // zz < 0
  MapError e = decode(negative);
  EXPECT_EQ(e.fault, MapFault::kCovarianceNotPd);
  EXPECT_NE(e.message.find("landmark 2"), std::string::npos) << e.message;
  std::vector<uint8_t> singular = b;  // rank 1: every entry 1e-6
  for (int k = 0; k < 6; ++k) putF64(&singular, cov + 8 * k, 1e-6);
  EXPECT_EQ(decode(singular).fault, MapFault::kCovarianceNotPd);
  std::vector<uint8_t> zero = b;
  for (int k = 0; k < 6; ++k) putF64(&zero, cov + 8 * k, 0.0);
  EXPECT_EQ(decode(zero).fault, MapFault::kCovarianceNotPd);
}

TEST(MapFile, SectionTableFaults) {
  const std::vector<uint8_t> b = encoded(sampleMap(2));
  std::vector<uint8_t> none = b;
  putU32(&none, 12, 0);
  EXPECT_EQ(decode(none).fault, MapFault::kSectionTable);
  std::vector<uint8_t> overlap = b;  // the calibration starts inside the meta section
  const uint64_t meta = sectionOffset(b, 0) + 4;
  for (int i = 0; i < 8; ++i) overlap[kHeaderBytes + kSectionEntryBytes + 8 + i] = uint8_t(meta >> (8 * i));
  EXPECT_EQ(decode(overlap).fault, MapFault::kSectionTable);
  std::vector<uint8_t> unknown_required = b;  // the calibration renamed to a type this reader does not know
  putU32(&unknown_required, kHeaderBytes + kSectionEntryBytes, 99);
  EXPECT_EQ(decode(unknown_required).fault, MapFault::kSectionTable);
  std::vector<uint8_t> missing = unknown_required;  // ... and optional: skipped, so the calibration is missing
  putU32(&missing, kHeaderBytes + kSectionEntryBytes + 4, 0);
  EXPECT_EQ(decode(missing).fault, MapFault::kMissingSection);
  std::vector<uint8_t> twice = b;
  putU32(&twice, kHeaderBytes + kSectionEntryBytes, kSectionMeta);
  EXPECT_EQ(decode(twice).fault, MapFault::kSectionTable);
}

TEST(MapFile, SizesMustAgreeWithTheContent) {
  const std::vector<uint8_t> b = encoded(sampleMap(3));
  std::vector<uint8_t> count = b;
  count[sectionOffset(b, 2) + 5] = 4;  // 4 landmarks claimed, 3 present
  EXPECT_EQ(decode(count).fault, MapFault::kBadSize);
  count[sectionOffset(b, 2) + 5 + 7] = 0xff;  // an absurd count, no allocation attempted
  EXPECT_EQ(decode(count).fault, MapFault::kBadSize);
  std::vector<uint8_t> unit = b;
  unit[sectionOffset(b, 0)] = 1;
  EXPECT_EQ(decode(unit).fault, MapFault::kUnit);
}

TEST(MapFile, WriterRefusesWhatTheReaderWouldRefuse) {
  MapData m = sampleMap(3);
  m.landmarks[1].covariance(2, 2) = -1.0;
  MapError e;
  EXPECT_TRUE(encodeMap(m, &e).empty());
  EXPECT_EQ(e.fault, MapFault::kCovarianceNotPd);
  m = sampleMap(3);
  m.landmarks[2].id = m.landmarks[0].id;
  encodeMap(m, &e);
  EXPECT_EQ(e.fault, MapFault::kBadValue);
  m = sampleMap(3);
  m.landmarks[0].descriptor.pop_back();
  encodeMap(m, &e);
  EXPECT_EQ(e.fault, MapFault::kDescriptorType);
  m = sampleMap(3);
  m.gravity_direction = Vec3(0, 9.81, 0);
  encodeMap(m, &e);
  EXPECT_EQ(e.fault, MapFault::kBadValue);
}

}  // namespace
}  // namespace map_file
}  // namespace hapi_eskf
