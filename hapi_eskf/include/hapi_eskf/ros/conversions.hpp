// Message <-> filter conversions of the nodelet. Pure functions (no node
// handle) so the covariance mapping and the cloud layout are unit-tested.
#pragma once

#include "hapi_eskf/backend/map_files.hpp"
#include "hapi_eskf/types.hpp"

#include <geometry_msgs/PoseWithCovariance.h>
#include <geometry_msgs/Transform.h>
#include <geometry_msgs/TwistWithCovariance.h>
#include <hapi_msgs/StereoLandmarks.h>
#include <sensor_msgs/PointCloud2.h>

#include <Eigen/Geometry>
#include <array>
#include <vector>

namespace hapi_eskf {
namespace ros_glue {

// hapi_msgs/StereoLandmarks -> StereoFrame (the message must have passed
// validateLandmarks; nothing is re-checked here).
StereoFrame toStereoFrame(const hapi_msgs::StereoLandmarks& msg);

// geometry_msgs/Transform <-> rigid transform (tf2_eigen; the quaternion is
// normalised on the way in: TF carries it as four independent doubles).
Eigen::Isometry3d toIsometry(const geometry_msgs::Transform& t);
geometry_msgs::Transform toTransform(const Eigen::Isometry3d& T);
// A position + orientation as a geometry_msgs::Pose (the one place where an
// Eigen pose becomes a message: odometry, pose and path share it).
geometry_msgs::Pose toPoseMsg(const Vec3& p, const Eigen::Quaterniond& q);
// A 6x6 covariance as the row-major, symmetrised array of ROS messages.
void toCovarianceMsg(const Eigen::Matrix<double, 6, 6>& S, boost::array<double, 36>* out);

// Pose of the camera in the published world frame: T_map_cam = T_map_world *
// T_world_cam, where `world` is the filter's world (the first camera) and
// T_map_world the fixed anchoring transform (identity unless ~base_frame).
// Kept as position and quaternion so that odometry, TF and path are all
// filled from this one value.
struct CameraInMap {
  Vec3 p = Vec3::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Eigen::Isometry3d isometry() const;
};
CameraInMap toCameraInMap(const PoseState& pose, const Eigen::Isometry3d& T_map_world);

// T_map_cam with its covariance as geometry_msgs/PoseWithCovariance.
// Covariance (ROS order [x y z rot_x rot_y rot_z], rotations about the fixed
// axes of header.frame_id): the filter's error state is [dp (world), dtheta
// (LOCAL, R = R_hat Exp(dtheta)), dv, dw (camera)] (docs/DESIGN.md "State and error state").
// R_hat Exp(dtheta) = Exp(R_hat dtheta) R_hat, so the global rotation error
// is R_map_cam dtheta and the position error R_map_world dp:
//   Sigma_pose = J C[0:6,0:6] J^T,  J = blockdiag(R_map_world, R_map_cam).
geometry_msgs::PoseWithCovariance toPoseWithCovariance(const CameraInMap& T_map_cam, const Mat12& C,
                                                       const Mat3& R_map_world);
// Same, from the filter pose: toCameraInMap + the above.
geometry_msgs::PoseWithCovariance toPoseWithCovariance(const PoseState& pose, const Mat12& C,
                                                       const Eigen::Isometry3d& T_map_world);

// Twist in the child (camera) frame, which is the frame the filter keeps v and
// w in, so its covariance is C[6:12, 6:12] unchanged ([vx vy vz wx wy wz]).
geometry_msgs::TwistWithCovariance toTwistWithCovariance(const PoseState& pose, const Mat12& C);

// The map point and its sigma are the core's (map_files.hpp).
using hapi_eskf::landmarkSigma;
using hapi_eskf::MapPoint;
std::vector<MapPoint> toMapPoints(const std::vector<LandmarkInfo>& landmarks, const Eigen::Isometry3d& T_map_world);

// sensor_msgs/PointCloud2 with fields x y z rgb sigma (FLOAT32; rgb packed
// 0x00RRGGBB into the float's bits as PCL/rviz expect) and id (UINT32).
// Unorganised (height 1), little-endian, dense.
sensor_msgs::PointCloud2 toPointCloud2(const std::vector<MapPoint>& points);

}  // namespace ros_glue
}  // namespace hapi_eskf
