// The running back end <-> a map file (map_session.hpp).
#include "hapi_eskf/session/map_session.hpp"

#include "hapi_eskf/eskf/eskf.hpp"
#include "hapi_eskf/map_file/map_landmarks.hpp"

#include <string>

namespace hapi_eskf {
namespace map_file {

MapError checkLoadable(const MapData& map, const EskfSettings& settings) {
  if (settings.backend_algorithm != BackendAlgorithm::kEskf)
    return mapError(MapFault::kBadValue, std::string("backend_algorithm ") + toString(settings.backend_algorithm) +
                                             " cannot load a map (eskf only)");
  if (settings.motion_model == MotionModelKind::kInertial && map.gravity_direction.norm() == 0.0)
    return mapError(MapFault::kBadValue,
                    "motion_model inertial needs the map's gravity direction (this map was saved without an IMU)");
  if (settings.ransac_iterations == 0)
    return mapError(MapFault::kBadValue, "ransac_iterations 0: no fit could place the camera in the map");
  const long room = static_cast<long>(settings.max_landmarks) - settings.max_new_landmarks;
  if (static_cast<long>(map.landmarks.size()) > room)
    return mapError(MapFault::kBadValue, std::to_string(map.landmarks.size()) +
                                             " landmarks do not fit max_landmarks - max_new_landmarks = " +
                                             std::to_string(room));
  return {};
}

MapError mapFromBackend(const SlamBackend& backend, const Eigen::Isometry3d& T_out_world, const MapData& header,
                        MapData* out, int* skipped) {
  const auto* eskf = dynamic_cast<const Eskf*>(&backend);
  if (!eskf) return mapError(MapFault::kBadValue, std::string("back end ") + backend.name() + " saves no map file");
  std::vector<LandmarkInfo> pool = eskf->landmarks();
  if (pool.empty()) return mapError(MapFault::kBadValue, "the pool is empty");
  const Mat3 R = T_out_world.linear();
  for (LandmarkInfo& l : pool) {
    l.position = T_out_world * l.position;
    l.covariance = R * l.covariance * R.transpose();
  }
  MapData map = header;
  map.gravity_direction = Vec3::Zero();
  const Vec3 g = eskf->state().g;
  if (eskf->settings().motion_model == MotionModelKind::kInertial && g.norm() > 0)
    map.gravity_direction = (R * g).normalized();
  map.landmarks = toMapLandmarks(pool, eskf->landmarkDescriptors(), map.descriptor_length, skipped);
  *out = std::move(map);
  return {};
}

MapError loadIntoBackend(const MapData& map, SlamBackend* backend) {
  auto* eskf = dynamic_cast<Eskf*>(backend);
  if (!eskf) return mapError(MapFault::kBadValue, std::string("back end ") + backend->name() + " loads no map");
  const Status st = eskf->loadMap(toPriorLandmarks(map), map.gravity_direction, map.keyframes);
  if (st != Status::kOk) return mapError(MapFault::kBadValue, std::string("the filter refused the map: ") + toString(st));
  return {};
}

}  // namespace map_file
}  // namespace hapi_eskf
