// Writes the seed corpus of the fuzz targets: a few valid inputs per target
// (and one near-miss each) in the record format of bounded_message.hpp.
//   make_fuzz_seeds <corpus folder>   -> <folder>/{landmarks,imu,image_pair,compressed,image_flow,surface_motion_flow,
//                                                 surface_input,dense_depth_pair,map_file,camera_info}/seed_*
// Deterministic (fixed seeds): rerunning it rewrites the same files.
#include "bounded_message.hpp"
#include "synthetic_frames.hpp"

#include "hapi_eskf/map_file/map_writer.hpp"
#include "hapi_surface/ply_io.hpp"

#include <hapi_msgs/ImageFlow.h>
#include <hapi_msgs/StereoLandmarks.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/image_encodings.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <sys/stat.h>

namespace {

using Bytes = std::vector<std::uint8_t>;

void write(const std::string& dir, const std::string& name, const Bytes& b) {
  mkdir(dir.c_str(), 0755);
  std::ofstream(dir + "/" + name, std::ios::binary).write(reinterpret_cast<const char*>(b.data()), b.size());
}

// Landmarks: a short synthetic sequence, a sequence with a NaN landmark and a
// backwards stamp, a sequence starting with an empty frame.
void landmarks(const std::string& dir) {
  hapi_eskf_test::SyntheticScene scene(40, 3);
  Bytes a;
  for (int i = 0; i < 4; ++i) hapi_fuzz::appendRecord(scene.frame(0.1 * i, ros::Time(10.0 + 0.1 * i), "cam"), &a);
  write(dir, "seed_sequence", a);
  Bytes b;
  hapi_msgs::StereoLandmarks bad = scene.frame(0.0, ros::Time(10.0), "cam");
  hapi_fuzz::appendRecord(bad, &b);
  bad.landmarks[0].position.x = std::numeric_limits<double>::quiet_NaN();
  bad.header.stamp = ros::Time(10.1);
  hapi_fuzz::appendRecord(bad, &b);
  hapi_fuzz::appendRecord(scene.frame(0.2, ros::Time(9.0), "cam"), &b);
  write(dir, "seed_bad_then_loop", b);
  Bytes c;
  hapi_msgs::StereoLandmarks empty = scene.frame(0.0, ros::Time(10.0), "cam");
  empty.landmarks.clear();
  empty.descriptors.clear();
  hapi_fuzz::appendRecord(empty, &c);
  for (int i = 1; i < 3; ++i) hapi_fuzz::appendRecord(scene.frame(0.1 * i, ros::Time(10.0 + 0.1 * i), "cam"), &c);
  write(dir, "seed_empty_first", c);
}

// IMU at 200 Hz from the first frame's stamp (imu_fuzzer.cpp: 100 s), in the
// camera frame: held still (gravity alignment), then turning and moving.
void imu(const std::string& dir) {
  auto sample = [](double t, double wx, double ay) {
    sensor_msgs::Imu m;
    m.header.stamp = ros::Time(t);
    m.header.frame_id = "camera";
    m.angular_velocity.x = wx;
    m.linear_acceleration.y = -9.81 + ay;
    return m;
  };
  Bytes still, moving;
  for (int i = 1; i <= 120; ++i) hapi_fuzz::appendRecord(sample(100.0 + 0.005 * i, 0.0, 0.0), &still);
  write(dir, "seed_still", still);
  for (int i = 1; i <= 160; ++i) {
    const double t = 0.005 * i;
    hapi_fuzz::appendRecord(sample(100.0 + t, t > 0.4 ? 0.5 * std::sin(6 * t) : 0.0, t > 0.4 ? std::cos(5 * t) : 0.0),
                            &moving);
  }
  write(dir, "seed_moving", moving);
  Bytes gap;
  for (int i = 1; i <= 80; ++i) hapi_fuzz::appendRecord(sample(100.0 + 0.005 * i + (i > 70 ? 0.3 : 0.0), 0, 0), &gap);
  hapi_fuzz::appendRecord(sample(100.1, 0, 0), &gap);  // out of order
  write(dir, "seed_gap_and_order", gap);
}

// A textured 96x72 pair: the right image is the left one shifted by 4 px.
cv::Mat texture(int w, int h) {
  cv::Mat img(h, w, CV_8UC1);
  cv::RNG rng(5);
  rng.fill(img, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(img, img, cv::Size(3, 3), 0.8);
  return img;
}

sensor_msgs::CameraInfo info(int w, int h, double tx) {
  sensor_msgs::CameraInfo c;
  c.header.frame_id = "cam";
  c.width = w;
  c.height = h;
  c.distortion_model = "plumb_bob";
  c.D = {0.0, 0.0, 0.0, 0.0, 0.0};
  c.K = {80.0, 0, w / 2.0, 0, 80.0, h / 2.0, 0, 0, 1};
  c.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  c.P = {80.0, 0, w / 2.0, tx, 0, 80.0, h / 2.0, 0, 0, 0, 1, 0};
  return c;
}

sensor_msgs::Image image(const cv::Mat& m, const std::string& encoding) {
  sensor_msgs::Image i;
  i.header.frame_id = "cam";
  i.header.stamp = ros::Time(1.0);
  i.width = m.cols;
  i.height = m.rows;
  i.encoding = encoding;
  i.step = static_cast<std::uint32_t>(m.step);
  i.data.assign(m.data, m.data + m.step * m.rows);
  return i;
}

void imagePairs(const std::string& dir) {
  const int w = 96, h = 72;
  const cv::Mat big = texture(w + 8, h);
  const cv::Mat left = big(cv::Rect(4, 0, w, h)).clone(), right = big(cv::Rect(0, 0, w, h)).clone();
  Bytes mono;
  hapi_fuzz::appendRecord(image(left, sensor_msgs::image_encodings::MONO8), &mono);
  hapi_fuzz::appendRecord(image(right, sensor_msgs::image_encodings::MONO8), &mono);
  hapi_fuzz::appendRecord(info(w, h, 0.0), &mono);
  hapi_fuzz::appendRecord(info(w, h, -80.0 * 0.05), &mono);
  write(dir, "seed_mono8", mono);
  cv::Mat lc, rc, l16, r16;
  cv::cvtColor(left, lc, cv::COLOR_GRAY2BGR);
  cv::cvtColor(right, rc, cv::COLOR_GRAY2BGR);
  left.convertTo(l16, CV_16U, 256.0);
  right.convertTo(r16, CV_16U, 256.0);
  Bytes other;
  hapi_fuzz::appendRecord(image(lc, sensor_msgs::image_encodings::BGR8), &other);
  hapi_fuzz::appendRecord(image(rc, sensor_msgs::image_encodings::BGR8), &other);
  hapi_fuzz::appendRecord(info(w, h, 0.0), &other);
  hapi_fuzz::appendRecord(info(w, h, -80.0 * 0.05), &other);
  hapi_fuzz::appendRecord(image(l16, sensor_msgs::image_encodings::MONO16), &other);
  hapi_fuzz::appendRecord(image(r16, sensor_msgs::image_encodings::MONO16), &other);
  hapi_fuzz::appendRecord(info(w, h, 0.0), &other);
  hapi_fuzz::appendRecord(info(w, h, -80.0 * 0.05), &other);
  write(dir, "seed_bgr8_then_mono16", other);
}

void compressed(const std::string& dir) {
  const cv::Mat grey = texture(64, 48);
  cv::Mat colour;
  cv::cvtColor(grey, colour, cv::COLOR_GRAY2BGR);
  auto encode = [](const cv::Mat& m, const std::string& ext, const std::string& format) {
    sensor_msgs::CompressedImage c;
    c.header.frame_id = "cam";
    c.format = format;
    cv::imencode(ext, m, c.data);
    Bytes out(ros::serialization::serializationLength(c));
    ros::serialization::OStream o(out.data(), static_cast<std::uint32_t>(out.size()));
    ros::serialization::serialize(o, c);
    return out;
  };
  write(dir, "seed_mono_png", encode(grey, ".png", "mono8; png compressed "));
  write(dir, "seed_rgb_jpeg", encode(colour, ".jpg", "rgb8; jpeg compressed bgr8"));
  cv::Mat m16;
  grey.convertTo(m16, CV_16U, 256.0);
  write(dir, "seed_mono16_png", encode(m16, ".png", "mono16; png compressed "));
}

// Image flow: a texture moving by a sub-pixel step in mono8; the same in
// other encodings (bgr8, big-endian mono16, a 32FC1 map with a NaN); and a
// sequence whose stamps go back, jump and whose size changes.
void imageFlow(const std::string& dir) {
  namespace enc = sensor_msgs::image_encodings;
  const int w = 64, h = 48;
  const cv::Mat big = texture(w + 8, h + 8);
  auto frame = [&](int k, const std::string& encoding, double t) {
    cv::Mat g = big(cv::Rect(k, k / 2, w, h)).clone(), m;
    if (encoding == enc::BGR8) cv::cvtColor(g, m, cv::COLOR_GRAY2BGR);
    else if (encoding == enc::MONO16) g.convertTo(m, CV_16U, 16.0);
    else if (encoding == enc::TYPE_32FC1) g.convertTo(m, CV_32F, 0.1);
    else m = g;
    if (encoding == enc::TYPE_32FC1) m.at<float>(3, 3) = std::numeric_limits<float>::quiet_NaN();
    sensor_msgs::Image i = image(m, encoding);
    i.header.stamp = ros::Time(t);
    if (encoding == enc::MONO16) {
      i.is_bigendian = 1;
      for (std::size_t b = 0; b + 1 < i.data.size(); b += 2) std::swap(i.data[b], i.data[b + 1]);
    }
    return i;
  };
  Bytes mono;
  for (int k = 0; k < 4; ++k) hapi_fuzz::appendRecord(frame(k, enc::MONO8, 1.0 + 0.025 * k), &mono);
  write(dir, "seed_mono8_sequence", mono);
  Bytes encodings;
  hapi_fuzz::appendRecord(frame(0, enc::BGR8, 1.0), &encodings);
  hapi_fuzz::appendRecord(frame(1, enc::MONO16, 1.025), &encodings);
  hapi_fuzz::appendRecord(frame(2, enc::TYPE_32FC1, 1.05), &encodings);
  write(dir, "seed_encodings", encodings);
  Bytes restarts;
  hapi_fuzz::appendRecord(frame(0, enc::MONO8, 2.0), &restarts);
  hapi_fuzz::appendRecord(frame(1, enc::MONO8, 1.9), &restarts);  // back
  hapi_fuzz::appendRecord(frame(2, enc::MONO8, 9.0), &restarts);  // gap
  sensor_msgs::Image small = image(big(cv::Rect(0, 0, 20, 16)).clone(), enc::MONO8);
  small.header.stamp = ros::Time(9.025);
  hapi_fuzz::appendRecord(small, &restarts);  // size change
  write(dir, "seed_restarts", restarts);
}

// Image flow of the imaging camera at 40 Hz on surface_motion_flow_fuzzer.cpp's
// clock (odometry from 1000 s, 40 ms per record): the skin sliding right,
// and a sequence with a first frame, an out-of-order flow, a NaN and a
// too-few-features status.
void surfaceMotionFlows(const std::string& dir) {
  auto flow = [](double t_prev, double t, double du, std::uint8_t status) {
    hapi_msgs::ImageFlow m;
    m.header.stamp = ros::Time(t);
    m.header.frame_id = "imaging_optical_frame";
    m.previous_stamp = ros::Time(t_prev);
    m.u = 319.5;
    m.v = 239.5;
    m.affine = {du, 0.0, 0.0, 0.0, 0.0, 0.0};
    for (int i = 0; i < 6; ++i) m.affine_covariance[7 * i] = 4e-4;
    m.inliers = m.tracked = 30;
    m.status = status;
    return m;
  };
  Bytes sliding, bad;
  for (int i = 1; i <= 12; ++i) {
    const double t = 1000.04 + 0.04 * i;
    hapi_fuzz::appendRecord(flow(t - 0.025, t, 0.05, hapi_msgs::ImageFlow::STATUS_OK), &sliding);
  }
  write(dir, "seed_sliding", sliding);
  hapi_fuzz::appendRecord(flow(0.0, 1000.05, 0.0, hapi_msgs::ImageFlow::STATUS_FIRST_FRAME), &bad);
  hapi_fuzz::appendRecord(flow(1000.05, 1000.075, 0.1, hapi_msgs::ImageFlow::STATUS_OK), &bad);
  hapi_fuzz::appendRecord(flow(1000.025, 1000.05, 0.1, hapi_msgs::ImageFlow::STATUS_OK), &bad);  // out of order
  hapi_fuzz::appendRecord(flow(1000.075, 1000.1, std::numeric_limits<double>::quiet_NaN(),
                               hapi_msgs::ImageFlow::STATUS_OK), &bad);
  hapi_fuzz::appendRecord(flow(1000.1, 1000.125, 0.0, hapi_msgs::ImageFlow::STATUS_TOO_FEW_FEATURES), &bad);
  hapi_fuzz::appendRecord(flow(1000.125, 1000.15, 40.0, hapi_msgs::ImageFlow::STATUS_OK), &bad);  // gated
  write(dir, "seed_bad_then_jump", bad);
}

// hapi_surface's inputs: a PLY file's bytes, then a depth image (a plane at
// 25 cm with holes) and imaging frames in several encodings.
void surfaceInput(const std::string& dir) {
  namespace enc = sensor_msgs::image_encodings;
  hapi_surface::Mesh mesh;
  mesh.vertices = {{0, 0, 0.25f}, {0.01f, 0, 0.25f}, {0, 0.01f, 0.25f}};
  mesh.normals = {{0, 0, -1}, {0, 0, -1}, {0, 0, -1}};
  mesh.faces = {{0, 1, 2}};
  mesh.values = {1.f, 2.f, std::numeric_limits<float>::quiet_NaN()};
  const std::string ply = hapi_surface::plyBytes(mesh, {});
  Bytes b;
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>(ply.size() >> (8 * i)));
  b.insert(b.end(), ply.begin(), ply.end());
  cv::Mat depth(48, 64, CV_32F, cv::Scalar(0.25f));
  depth.at<float>(5, 5) = std::numeric_limits<float>::quiet_NaN();
  depth.at<float>(6, 6) = std::numeric_limits<float>::infinity();
  sensor_msgs::Image d = image(depth, enc::TYPE_32FC1);
  d.header.stamp = ros::Time(1.0);
  hapi_fuzz::appendRecord(d, &b);
  const cv::Mat grey = texture(64, 48);
  cv::Mat colour, wide, perfusion;
  cv::cvtColor(grey, colour, cv::COLOR_GRAY2BGR);
  grey.convertTo(wide, CV_16U, 16.0);
  grey.convertTo(perfusion, CV_32F, 0.5);
  perfusion.at<float>(10, 10) = std::numeric_limits<float>::quiet_NaN();
  hapi_fuzz::appendRecord(image(grey, enc::MONO8), &b);
  hapi_fuzz::appendRecord(image(colour, enc::BGR8), &b);
  sensor_msgs::Image big_endian = image(wide, enc::MONO16);
  big_endian.is_bigendian = 1;
  big_endian.header.seq = 1;  // a camera size that does not match
  hapi_fuzz::appendRecord(big_endian, &b);
  hapi_fuzz::appendRecord(image(perfusion, enc::TYPE_32FC1), &b);
  write(dir, "seed_depth_then_imaging", b);
}


// A saved landmark map (hapi_eskf/map_file): three landmarks with an IMU,
// the same with two keyframes, an empty map without one, and a near miss (a
// NaN in a covariance).
void mapFile(const std::string& dir) {
  using namespace hapi_eskf::map_file;
  MapData m;
  m.camera_frame = "stereo_left_optical_frame";
  m.gravity_direction = Eigen::Vector3d(0.0, 1.0, 0.0);
  m.created = 1795600000.0;
  m.calibration.width = 752;
  m.calibration.height = 480;
  m.calibration.fx = m.calibration.fy = 458.0;
  m.calibration.cx = 376.0;
  m.calibration.cy = 240.0;
  m.calibration.baseline = 0.11;
  m.calibration.has_imu = true;
  m.calibration.imu_cam.p_imu_cam = Eigen::Vector3d(-0.02, -0.06, 0.01);
  for (int i = 0; i < 3; ++i) {
    MapLandmark l;
    l.id = 10 + i;
    l.position = Eigen::Vector3d(0.01 * i, -0.02, 0.25);
    l.covariance = Eigen::Vector3d(1e-8, 1e-8, 4e-7).asDiagonal();
    l.covariance(0, 2) = l.covariance(2, 0) = 5e-9;
    l.times_observed = 1 + 4 * i;
    l.descriptor.assign(32, static_cast<std::uint8_t>(0x5a + i));
    m.landmarks.push_back(l);
  }
  MapError error;
  Bytes b = encodeMap(m, &error);
  write(dir, "seed_three_landmarks", b);
  const std::size_t last_zz = b.size() - 32 - 4 - 8;  // the last landmark's covariance zz
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(b.data() + last_zz, &nan, sizeof(nan));
  write(dir, "seed_nan_covariance", b);
  // Two keyframes of two points each (the optional keyframes section).
  for (int k = 0; k < 2; ++k) {
    hapi_eskf::Keyframe kf;
    kf.id = 1 + k;
    kf.stamp = 1795600000.0 + 0.1 * k;
    kf.T_map_cam.translation() = Eigen::Vector3d(0.01 * k, 0.0, 0.0);
    kf.pose_covariance = hapi_eskf::Mat6::Identity() * 1e-6;
    kf.descriptor_length = 32;
    for (int i = 0; i < 2; ++i) {
      kf.points.emplace_back(0.01 * i, -0.02, 0.25);
      kf.point_covariances.push_back(Eigen::Vector3d(1e-8, 1e-8, 4e-7).asDiagonal());
      kf.descriptors.insert(kf.descriptors.end(), 32, static_cast<std::uint8_t>(0x5a + i));
    }
    m.keyframes.push_back(kf);
  }
  write(dir, "seed_two_keyframes", encodeMap(m, &error));
  m.keyframes.clear();
  m.landmarks.clear();
  m.gravity_direction.setZero();
  m.calibration.has_imu = false;
  m.calibration.imu_cam = hapi_eskf::CameraExtrinsic();
  write(dir, "seed_empty_map", encodeMap(m, &error));
}

// EskfNodelet's left and right camera_info: a rectified pair (the right's
// Tx = -fx * 0.11 m), and a near miss (the right's Tx of the wrong sign).
void cameraInfo(const std::string& dir) {
  Bytes pair;
  hapi_fuzz::appendRecord(info(752, 480, 0.0), &pair);
  hapi_fuzz::appendRecord(info(752, 480, -80.0 * 0.11), &pair);
  write(dir, "seed_rectified_pair", pair);
  Bytes wrong_sign;
  hapi_fuzz::appendRecord(info(752, 480, 0.0), &wrong_sign);
  hapi_fuzz::appendRecord(info(752, 480, 80.0 * 0.11), &wrong_sign);
  write(dir, "seed_negative_baseline", wrong_sign);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_fuzz_seeds <corpus folder>\n");
    return 2;
  }
  const std::string out = argv[1];
  mkdir(out.c_str(), 0755);
  landmarks(out + "/landmarks");
  imu(out + "/imu");
  imagePairs(out + "/image_pair");
  imagePairs(out + "/dense_depth_pair");  // DenseDepthNodelet takes the same pair
  compressed(out + "/compressed");
  imageFlow(out + "/image_flow");
  surfaceMotionFlows(out + "/surface_motion_flow");
  surfaceInput(out + "/surface_input");
  mapFile(out + "/map_file");
  cameraInfo(out + "/camera_info");
  return 0;
}
