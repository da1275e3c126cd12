// Message conversions shared by the bag writers (see bag_messages.hpp).
#include "bag_messages.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "hapi_sim/text_format.hpp"

namespace hapi_sim {

ros::Time stampAt(int64_t ns) {
  constexpr int64_t kEpochSec = 1000000000;
  const int64_t total = kEpochSec * 1000000000LL + ns;
  return ros::Time(static_cast<uint32_t>(total / 1000000000LL), static_cast<uint32_t>(total % 1000000000LL));
}

sensor_msgs::CameraInfo toCameraInfoMsg(const CameraInfoData& d, const std_msgs::Header& h) {
  sensor_msgs::CameraInfo m;
  m.header = h;
  m.width = d.width;
  m.height = d.height;
  m.distortion_model = d.distortion_model;
  m.D = d.D;
  for (int i = 0; i < 9; ++i) { m.K[i] = d.K[i]; m.R[i] = d.R[i]; }
  for (int i = 0; i < 12; ++i) m.P[i] = d.P[i];
  return m;
}

sensor_msgs::Image toImageMsg(const cv::Mat& mono, const std_msgs::Header& h) {
  sensor_msgs::Image m;
  m.header = h;
  m.height = mono.rows;
  m.width = mono.cols;
  m.encoding = "mono8";
  m.is_bigendian = 0;
  m.step = mono.cols;
  m.data.resize(static_cast<size_t>(mono.rows) * mono.cols);
  for (int r = 0; r < mono.rows; ++r)
    std::copy(mono.ptr<uint8_t>(r), mono.ptr<uint8_t>(r) + mono.cols, m.data.begin() + static_cast<size_t>(r) * mono.cols);
  return m;
}

geometry_msgs::TransformStamped toTransformMsg(const ros::Time& t, const std::string& parent, const std::string& child,
                                               const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  geometry_msgs::TransformStamped tf;
  tf.header.stamp = t;
  tf.header.frame_id = parent;
  tf.child_frame_id = child;
  tf.transform.translation.x = p.x();
  tf.transform.translation.y = p.y();
  tf.transform.translation.z = p.z();
  tf.transform.rotation.x = q.x();
  tf.transform.rotation.y = q.y();
  tf.transform.rotation.z = q.z();
  tf.transform.rotation.w = q.w();
  return tf;
}

nav_msgs::Odometry toOdometryMsg(const ros::Time& t, const std::string& frame, const std::string& child,
                                 const MotionSample& m) {
  nav_msgs::Odometry o;
  o.header.stamp = t;
  o.header.frame_id = frame;
  o.child_frame_id = child;
  o.pose.pose.position.x = m.p.x();
  o.pose.pose.position.y = m.p.y();
  o.pose.pose.position.z = m.p.z();
  o.pose.pose.orientation.x = m.q.x();
  o.pose.pose.orientation.y = m.q.y();
  o.pose.pose.orientation.z = m.q.z();
  o.pose.pose.orientation.w = m.q.w();
  const Eigen::Vector3d v_child = m.q.conjugate() * m.v;  // REP-105: twist in the child frame
  o.twist.twist.linear.x = v_child.x();
  o.twist.twist.linear.y = v_child.y();
  o.twist.twist.linear.z = v_child.z();
  o.twist.twist.angular.x = m.omega.x();
  o.twist.twist.angular.y = m.omega.y();
  o.twist.twist.angular.z = m.omega.z();
  return o;
}

std::string globeInfoYaml(double radius, const Eigen::Vector3d& centre, const std::string& frame, uint32_t seed,
                          const std::string& texture) {
  std::ostringstream y;
  y << "radius: " << formatNumber(radius) << "\n"
    << "centre: [" << formatNumber(centre.x()) << ", " << formatNumber(centre.y()) << ", " << formatNumber(centre.z())
    << "]\n"
    << "frame_id: " << frame << "\n"
    << "seed: " << seed << "\n"
    << "texture: \"" << texture << "\"\n";
  return y.str();
}

double parseNumberArg(const std::string& key, const std::string& v) {
  size_t n = 0;
  double d = 0;
  try {
    d = std::stod(v, &n);
  } catch (const std::exception&) {
    n = 0;
  }
  if (n != v.size() || n == 0 || !std::isfinite(d)) throw std::invalid_argument("invalid number for " + key + ": '" + v + "'");
  return d;
}

}  // namespace hapi_sim
