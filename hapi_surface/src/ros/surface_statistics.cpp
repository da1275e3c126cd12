#include "surface_statistics.hpp"

#include <diagnostic_msgs/DiagnosticStatus.h>

namespace hapi_surface {
namespace ros_glue {

void SurfaceStatistics::reject(Counter* counter, SurfaceStatus why) {
  ++*counter;
  std::lock_guard<std::mutex> lk(mu_);
  ++reasons_[std::string("rejected: ") + toString(why)];
}

void SurfaceStatistics::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  const std::uint64_t depth = depth_received, used = keyframes + keyframes_unsettled + depth_skipped + time_jumps, imaging = imaging_received,
                      projected = imaging_projected + imaging_throttled;
  if (depth > last_depth_ && used == last_used_)
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "depth images arrive but none is used (see the rejections)");
  else if (imaging > last_imaging_ && projected == last_projected_)
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "imaging frames arrive but none is projected");
  else
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "ok");
  last_depth_ = depth;
  last_used_ = used;
  last_imaging_ = imaging;
  last_projected_ = projected;
  const std::pair<const char*, const Counter*> keys[] = {
      {"depth received", &depth_received},     {"depth rejected", &depth_rejected},
      {"depth without TF", &depth_no_tf},      {"depth out of order", &depth_out_of_order},
      {"time jumps (reset)", &time_jumps},     {"keyframes", &keyframes},
      {"depth not keyframes", &depth_skipped}, {"confidence missing", &confidence_missing},
      {"camera_info rejected", &camera_info_rejected}, {"imaging received", &imaging_received},
      {"imaging projected", &imaging_projected}, {"imaging rejected", &imaging_rejected},
      {"imaging without TF", &imaging_no_tf},  {"imaging throttled", &imaging_throttled},
      {"rebuilds", &rebuilds},                 {"meshes published", &meshes_published},
      {"saves", &saves},                       {"saves failed", &saves_failed},
      {"mesh vertices", &vertices},            {"mesh faces", &faces},
      {"keyframes stored", &keyframes_stored},
      {"keyframes before the filter settled", &keyframes_unsettled},
      {"keyframes waiting for a settled filter", &keyframes_waiting},
      {"early keyframes registered and fused", &early_keyframes_fused},
      {"early keyframes discarded", &early_keyframes_discarded},
      {"keyframes registered", &keyframes_registered},
      {"keyframes not registered (filter pose)", &keyframes_unregistered},
      {"odometry rejected", &odom_rejected}};
  for (const auto& k : keys) stat.add(k.first, static_cast<unsigned long long>(k.second->load()));
  stat.add("integration", on_gpu ? "cuda" : "cpu");
  std::lock_guard<std::mutex> lk(mu_);
  for (const auto& r : reasons_) stat.add(r.first, static_cast<unsigned long long>(r.second));
}

}  // namespace ros_glue
}  // namespace hapi_surface
