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

}  // namespace hapi_sim
