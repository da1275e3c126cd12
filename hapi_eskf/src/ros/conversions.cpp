#include "hapi_eskf/ros/conversions.hpp"

#include "hapi_eskf/eskf/motion_model.hpp"

#include <sensor_msgs/point_cloud2_iterator.h>
#include <tf2_eigen/tf2_eigen.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstring>

namespace hapi_eskf {
namespace ros_glue {

StereoFrame toStereoFrame(const hapi_msgs::StereoLandmarks& msg) {
  StereoFrame f;
  f.stamp = msg.header.stamp.toSec();
  f.descriptor_length = static_cast<int>(msg.descriptor_length);
  f.descriptors = msg.descriptors;
  f.measurements.resize(msg.landmarks.size());
  for (std::size_t i = 0; i < msg.landmarks.size(); ++i) {
    const auto& l = msg.landmarks[i];
    StereoMeasurement& m = f.measurements[i];
    tf2::fromMsg(l.position, m.z);
    m.Cz = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(l.position_covariance.data());
    m.frontend_id = l.id;
    m.response = l.response;
    m.rgb = {{l.r, l.g, l.b}};
  }
  return f;
}

Eigen::Isometry3d toIsometry(const geometry_msgs::Transform& t) {
  // Not tf2::transformToEigen: it takes the quaternion as it comes.
  Eigen::Quaterniond q;
  Vec3 p;
  tf2::fromMsg(t.rotation, q);
  tf2::fromMsg(t.translation, p);
  return Eigen::Translation3d(p) * q.normalized();
}

geometry_msgs::Transform toTransform(const Eigen::Isometry3d& T) { return tf2::eigenToTransform(T).transform; }

geometry_msgs::Pose toPoseMsg(const Vec3& p, const Eigen::Quaterniond& q) {
  // Not tf2::toMsg(Isometry3d): that goes through the rotation matrix and
  // flips the quaternion's sign to w >= 0; the filter's q is published as is.
  geometry_msgs::Pose out;
  out.position = tf2::toMsg(p);
  out.orientation = tf2::toMsg(q);
  return out;
}

void toCovarianceMsg(const Eigen::Matrix<double, 6, 6>& S, boost::array<double, 36>* out) {
  // Symmetrised: the filter's blocks are symmetric only to rounding, and ROS
  // consumers (rviz, robot_localization) factorise the message's matrix.
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) (*out)[6 * r + c] = 0.5 * (S(r, c) + S(c, r));
}

Eigen::Isometry3d CameraInMap::isometry() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q.normalized().toRotationMatrix();
  T.translation() = p;
  return T;
}

CameraInMap toCameraInMap(const PoseState& pose, const Eigen::Isometry3d& T_map_world) {
  CameraInMap out;
  out.q = Eigen::Quaterniond(T_map_world.linear()) * pose.q.normalized();
  out.p = T_map_world * pose.p;
  return out;
}

geometry_msgs::PoseWithCovariance toPoseWithCovariance(const CameraInMap& T_map_cam, const Mat12& C,
                                                       const Mat3& R_map_world) {
  geometry_msgs::PoseWithCovariance out;
  out.pose = toPoseMsg(T_map_cam.p, T_map_cam.q);
  // World axes (poseCovarianceInWorldAxes), then the map's: R_map_world on
  // both blocks.
  PoseState in_map;
  in_map.q = Eigen::Quaterniond(R_map_world).conjugate() * T_map_cam.q;  // the camera in the world
  Mat6 J = Mat6::Zero();
  J.block<3, 3>(0, 0) = R_map_world;
  J.block<3, 3>(3, 3) = R_map_world;
  toCovarianceMsg(J * poseCovarianceInWorldAxes(in_map, C) * J.transpose(), &out.covariance);
  return out;
}

geometry_msgs::PoseWithCovariance toPoseWithCovariance(const PoseState& pose, const Mat12& C,
                                                       const Eigen::Isometry3d& T_map_world) {
  return toPoseWithCovariance(toCameraInMap(pose, T_map_world), C, T_map_world.linear());
}

geometry_msgs::TwistWithCovariance toTwistWithCovariance(const PoseState& pose, const Mat12& C) {
  geometry_msgs::TwistWithCovariance out;
  tf2::toMsg(pose.v, out.twist.linear);
  tf2::toMsg(pose.w, out.twist.angular);
  toCovarianceMsg(C.block<6, 6>(kIdxV, kIdxV), &out.covariance);
  return out;
}

std::vector<MapPoint> toMapPoints(const std::vector<LandmarkInfo>& landmarks, const Eigen::Isometry3d& T_map_world) {
  std::vector<MapPoint> out;
  out.reserve(landmarks.size());
  for (const LandmarkInfo& l : landmarks) {
    MapPoint p;
    p.position = T_map_world * l.position;
    p.rgb = l.rgb;
    // A rigid change of frame rotates the ellipsoid, its eigenvalues stay.
    p.sigma = static_cast<float>(landmarkSigma(l.covariance));
    p.id = static_cast<uint32_t>(l.id & 0xffffffffu);
    out.push_back(p);
  }
  return out;
}

sensor_msgs::PointCloud2 toPointCloud2(const std::vector<MapPoint>& points) {
  sensor_msgs::PointCloud2 cloud;
  sensor_msgs::PointCloud2Modifier mod(cloud);
  mod.setPointCloud2Fields(6, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32,
                           "z", 1, sensor_msgs::PointField::FLOAT32, "rgb", 1, sensor_msgs::PointField::FLOAT32,
                           "sigma", 1, sensor_msgs::PointField::FLOAT32, "id", 1, sensor_msgs::PointField::UINT32);
  mod.resize(points.size());
  cloud.height = 1;
  cloud.width = static_cast<uint32_t>(points.size());
  cloud.is_dense = true;
  // PointCloud2Iterator starts at &data.front(), undefined on an empty buffer
  // (UBSan: "reference binding to null pointer"): an empty map (after a
  // reset) is the header and fields alone.
  if (points.empty()) return cloud;
  sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z"), rgb(cloud, "rgb"),
      sigma(cloud, "sigma");
  sensor_msgs::PointCloud2Iterator<uint32_t> id(cloud, "id");
  for (const MapPoint& p : points) {
    *x = static_cast<float>(p.position.x());
    *y = static_cast<float>(p.position.y());
    *z = static_cast<float>(p.position.z());
    const uint32_t packed = (uint32_t(p.rgb[0]) << 16) | (uint32_t(p.rgb[1]) << 8) | uint32_t(p.rgb[2]);
    float packed_f;
    std::memcpy(&packed_f, &packed, sizeof(float));
    *rgb = packed_f;
    *sigma = p.sigma;
    *id = p.id;
    ++x, ++y, ++z, ++rgb, ++sigma, ++id;
  }
  return cloud;
}

}  // namespace ros_glue
}  // namespace hapi_eskf
