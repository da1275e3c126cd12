// Message conversions shared by the bag writers (see bag_messages.hpp).
#include "bag_messages.hpp"

#include <tf2_eigen/tf2_eigen.h>

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
  o.pose.pose = toPoseMsg(m.p, m.q);
  const Eigen::Vector3d v_child = m.q.conjugate() * m.v;  // REP-105: twist in the child frame
  tf2::toMsg(v_child, o.twist.twist.linear);
  tf2::toMsg(m.omega, o.twist.twist.angular);
  return o;
}

hapi_msgs::SurfaceMotion toSurfaceMotionMsg(const ros::Time& t, const std::string& frame, const SurfaceMotionTruth& m) {
  static_assert(SurfaceMotionTruth::kStatusOk == hapi_msgs::SurfaceMotion::STATUS_OK &&
                    SurfaceMotionTruth::kStatusRayMissesMap == hapi_msgs::SurfaceMotion::STATUS_RAY_MISSES_MAP,
                "the core's status codes are the message's");
  hapi_msgs::SurfaceMotion s;
  s.header.stamp = t;
  s.header.frame_id = frame;
  s.status = static_cast<uint8_t>(m.status());
  if (!m.hit) s.status_message = "the pixel's ray misses the scene";
  s.u = m.pixel.x();
  s.v = m.pixel.y();
  s.frame_rate = m.frame_rate;
  s.point = tf2::toMsg(m.point);
  tf2::toMsg(m.normal, s.normal);
  tf2::toMsg(m.surface_velocity, s.surface_velocity);
  s.speed = m.speed;
  s.normal_velocity = m.normal_velocity;
  s.image_velocity = {m.image_velocity.x(), m.image_velocity.y()};
  return s;
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
