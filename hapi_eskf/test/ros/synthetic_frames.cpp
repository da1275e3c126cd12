#include "synthetic_frames.hpp"

#include <cmath>

namespace hapi_eskf_test {

sensor_msgs::CameraInfo stereoCameraInfo(bool right, const std::string& frame_id) {
  sensor_msgs::CameraInfo c;
  c.header.frame_id = frame_id;
  c.width = 640;
  c.height = 480;
  c.distortion_model = "plumb_bob";
  c.D.assign(5, 0.0);
  c.K = {kCameraInfoFocal, 0, 320, 0, kCameraInfoFocal, 240, 0, 0, 1};
  c.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  c.P = {kCameraInfoFocal, 0, 320, right ? -kCameraInfoFocal * kCameraInfoBaseline : 0.0,
         0, kCameraInfoFocal, 240, 0, 0, 0, 1, 0};
  return c;
}

std::array<ros::Publisher, 2> latchStereoCameraInfo(ros::NodeHandle& nh, const std::string& frame_id) {
  std::array<ros::Publisher, 2> pubs;
  for (int right = 0; right < 2; ++right) {
    pubs[right] = nh.advertise<sensor_msgs::CameraInfo>(right ? "/eskf/right/camera_info" : "/eskf/left/camera_info",
                                                        1, true);
    pubs[right].publish(stereoCameraInfo(right, frame_id));
  }
  return pubs;
}

SyntheticScene::SyntheticScene(int n_points, unsigned seed, double sigma) : rng_(seed), sigma_(sigma) {
  std::uniform_real_distribution<double> ux(-3.0, 3.0), uy(-2.0, 2.0), uz(3.0, 7.0);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int i = 0; i < n_points; ++i) {
    points_.emplace_back(ux(rng_), uy(rng_), uz(rng_));
    std::array<uint8_t, 32> d;
    for (auto& b : d) b = static_cast<uint8_t>(byte(rng_));
    descriptors_.push_back(d);
    colours_.push_back({{static_cast<uint8_t>(byte(rng_)), static_cast<uint8_t>(byte(rng_)), 128}});
  }
}

Eigen::Isometry3d SyntheticScene::pose(double t) const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.25 * t, 0.05 * std::sin(1.5 * t), 0.1 * t);
  T.linear() = Eigen::AngleAxisd(0.08 * std::sin(0.8 * t), Eigen::Vector3d::UnitY()).toRotationMatrix();
  return T;
}

hapi_msgs::StereoLandmarks SyntheticScene::frame(double t, const ros::Time& stamp, const std::string& frame_id) {
  hapi_msgs::StereoLandmarks m;
  m.header.stamp = stamp;
  m.header.frame_id = frame_id;
  m.descriptor_type = hapi_msgs::StereoLandmarks::DESCRIPTOR_ORB;
  m.descriptor_length = 32;
  const Eigen::Isometry3d T_wc = pose(t);
  const Eigen::Isometry3d T_cw = T_wc.inverse();
  std::normal_distribution<double> noise(0.0, sigma_);
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const Eigen::Vector3d pc = T_cw * points_[i];
    if (pc.z() < 0.5 || std::abs(pc.x() / pc.z()) > 1.0 || std::abs(pc.y() / pc.z()) > 0.7) continue;
    hapi_msgs::StereoLandmark l;
    l.id = static_cast<uint32_t>(m.landmarks.size());
    l.position.x = pc.x() + noise(rng_);
    l.position.y = pc.y() + noise(rng_);
    l.position.z = pc.z() + noise(rng_);
    const double v = sigma_ * sigma_;
    l.position_covariance = {v, 0, 0, 0, v, 0, 0, 0, v};
    l.response = 100.f - static_cast<float>(pc.z());
    l.r = colours_[i][0];
    l.g = colours_[i][1];
    l.b = colours_[i][2];
    m.landmarks.push_back(l);
    m.descriptors.insert(m.descriptors.end(), descriptors_[i].begin(), descriptors_[i].end());
  }
  return m;
}

}  // namespace hapi_eskf_test
