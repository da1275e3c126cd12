#include "surface_motion_conversions.hpp"

#include <sensor_msgs/point_cloud2_iterator.h>

#include <cmath>

namespace hapi_eskf {
namespace ros_glue {

using surface_motion::MotionStatus;

surface_motion::FlowMeasurement toFlowMeasurement(const hapi_msgs::ImageFlow& msg) {
  surface_motion::FlowMeasurement f;
  f.t_prev = msg.previous_stamp.toSec();
  f.t = msg.header.stamp.toSec();
  f.u = msg.u;
  f.v = msg.v;
  for (int i = 0; i < 6; ++i) f.affine[i] = msg.affine[i];
  for (int i = 0; i < 36; ++i) f.covariance[i] = msg.affine_covariance[i];
  f.inliers = msg.inliers;
  f.tracked = msg.tracked;
  f.status = msg.status;
  return f;
}

surface_motion::CameraOdometry toCameraOdometry(const nav_msgs::Odometry& msg) {
  surface_motion::CameraOdometry o;
  o.t = msg.header.stamp.toSec();
  const auto& p = msg.pose.pose;
  Eigen::Quaterniond q(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z);
  // A quaternion far from unit length is not a rotation: NaN makes valid() fail.
  if (!(std::abs(q.norm() - 1.0) < 1e-3)) q.coeffs().setConstant(std::nan(""));
  o.T_world_cam.linear() = q.normalized().toRotationMatrix();
  o.T_world_cam.translation() = Vec3(p.position.x, p.position.y, p.position.z);
  const auto& t = msg.twist.twist;
  o.v = Vec3(t.linear.x, t.linear.y, t.linear.z);
  o.w = Vec3(t.angular.x, t.angular.y, t.angular.z);
  for (int i = 0; i < 36; ++i) o.twist_covariance(i / 6, i % 6) = msg.twist.covariance[i];
  return o;
}

std::string toImagingCamera(const sensor_msgs::CameraInfo& msg, double frame_rate, surface_motion::ImagingCamera* out) {
  surface_motion::ImagingCamera c;
  c.fx = msg.K[0];
  c.fy = msg.K[4];
  c.cx = msg.K[2];
  c.cy = msg.K[5];
  c.width = static_cast<int>(msg.width);
  c.height = static_cast<int>(msg.height);
  c.frame_rate = frame_rate;
  if (!msg.D.empty()) {
    if (msg.distortion_model != "plumb_bob" || msg.D.size() < 4 || msg.D.size() > 5)
      return "distortion model '" + msg.distortion_model + "' with " + std::to_string(msg.D.size()) +
             " coefficients: only plumb_bob (4 or 5) is supported";
    for (std::size_t i = 0; i < msg.D.size(); ++i) c.distortion[i] = msg.D[i];
  }
  std::string why = c.check();
  if (why.empty()) *out = c;
  return why;
}

std::string toPoints(const sensor_msgs::PointCloud2& msg, std::vector<Vec3>* out) {
  int xyz = 0;
  uint8_t type = 0;
  for (const auto& f : msg.fields)
    if (f.name == "x" || f.name == "y" || f.name == "z") {
      ++xyz;
      if (type != 0 && f.datatype != type) return "x, y, z of different types";
      type = f.datatype;
      if (f.count != 1) return "x, y, z must have count 1";
    }
  if (xyz != 3) return "no x, y, z fields";
  if (type != sensor_msgs::PointField::FLOAT32 && type != sensor_msgs::PointField::FLOAT64)
    return "x, y, z must be FLOAT32 or FLOAT64";
  // The iterators walk the data by point_step to its end: dense rows only.
  const std::size_t n = static_cast<std::size_t>(msg.width) * msg.height;
  if (msg.point_step == 0 || msg.row_step != static_cast<std::size_t>(msg.width) * msg.point_step ||
      msg.data.size() != n * msg.point_step)
    return "data size is not width * height * point_step (row_step = width * point_step)";
  for (const auto& f : msg.fields)
    if ((f.name == "x" || f.name == "y" || f.name == "z") &&
        f.offset + (type == sensor_msgs::PointField::FLOAT32 ? 4u : 8u) > msg.point_step)
      return "field " + f.name + " beyond point_step";
  out->clear();
  out->reserve(n);
  if (n == 0) return "";
  if (type == sensor_msgs::PointField::FLOAT32) {
    sensor_msgs::PointCloud2ConstIterator<float> x(msg, "x"), y(msg, "y"), z(msg, "z");
    for (; x != x.end(); ++x, ++y, ++z)
      if (std::isfinite(*x) && std::isfinite(*y) && std::isfinite(*z)) out->emplace_back(*x, *y, *z);
  } else {
    sensor_msgs::PointCloud2ConstIterator<double> x(msg, "x"), y(msg, "y"), z(msg, "z");
    for (; x != x.end(); ++x, ++y, ++z)
      if (std::isfinite(*x) && std::isfinite(*y) && std::isfinite(*z)) out->emplace_back(*x, *y, *z);
  }
  return "";
}

hapi_msgs::SurfaceMotion toMessage(const surface_motion::SurfaceMotionOutput& out, const ros::Time& stamp,
                                   const std::string& frame) {
  hapi_msgs::SurfaceMotion m;
  m.header.stamp = stamp;
  m.header.frame_id = frame;
  m.status = static_cast<uint8_t>(out.status);
  m.status_message = out.message;
  m.u = out.u;
  m.v = out.v;
  m.frame_rate = out.frame_rate;
  m.flow_fused = out.flow_fused;
  if (out.status != MotionStatus::kOk) return m;  // never a made-up value
  const surface_motion::SurfaceVelocity& s = out.velocity;
  m.point.x = s.point.x();
  m.point.y = s.point.y();
  m.point.z = s.point.z();
  m.normal.x = s.normal.x();
  m.normal.y = s.normal.y();
  m.normal.z = s.normal.z();
  m.surface_velocity.x = s.surface_velocity.x();
  m.surface_velocity.y = s.surface_velocity.y();
  m.surface_velocity.z = s.surface_velocity.z();
  m.speed = s.speed();
  for (int i = 0; i < 9; ++i) m.surface_velocity_covariance[i] = s.surface_velocity_covariance(i / 3, i % 3);
  m.normal_velocity = s.normal_velocity;
  m.normal_velocity_variance = s.normal_velocity_variance;
  m.image_velocity[0] = s.image_velocity.x();
  m.image_velocity[1] = s.image_velocity.y();
  for (int i = 0; i < 4; ++i) m.image_velocity_covariance[i] = s.image_velocity_covariance(i / 2, i % 2);
  return m;
}

visualization_msgs::Marker toMarker(const hapi_msgs::SurfaceMotion& msg, double marker_scale) {
  visualization_msgs::Marker mk;
  mk.header = msg.header;
  mk.ns = "surface_motion";
  mk.id = 0;
  mk.type = visualization_msgs::Marker::ARROW;
  if (msg.status != hapi_msgs::SurfaceMotion::STATUS_OK) {
    mk.action = visualization_msgs::Marker::DELETE;
    return mk;
  }
  mk.action = visualization_msgs::Marker::ADD;
  mk.pose.orientation.w = 1;
  geometry_msgs::Point a = msg.point, b = msg.point;
  b.x += marker_scale * msg.surface_velocity.x;
  b.y += marker_scale * msg.surface_velocity.y;
  b.z += marker_scale * msg.surface_velocity.z;
  mk.points = {a, b};
  mk.scale.x = 0.002;  // shaft diameter [m]
  mk.scale.y = 0.004;  // head diameter
  mk.scale.z = 0.004;  // head length
  mk.color.r = 1.0f;
  mk.color.g = 0.5f;
  mk.color.a = 1.0f;
  return mk;
}

}  // namespace ros_glue
}  // namespace hapi_eskf
