// The pool <-> map file landmarks (map_landmarks.hpp).
#include "hapi_eskf/map_file/map_landmarks.hpp"

#include "hapi_eskf/map_file/map_checks.hpp"

#include <algorithm>

namespace hapi_eskf {
namespace map_file {

std::vector<MapLandmark> toMapLandmarks(const std::vector<LandmarkInfo>& pool, const std::vector<uint8_t>& descriptors,
                                        uint32_t descriptor_length, int* skipped) {
  std::vector<MapLandmark> out;
  out.reserve(pool.size());
  *skipped = 0;
  for (std::size_t k = 0; k < pool.size(); ++k) {
    MapLandmark l;
    l.id = pool[k].id;
    l.position = pool[k].position;
    l.covariance = 0.5 * (pool[k].covariance + pool[k].covariance.transpose());
    l.times_observed = static_cast<uint32_t>(std::max(1, pool[k].times_observed));
    if ((k + 1) * descriptor_length <= descriptors.size())
      l.descriptor.assign(descriptors.begin() + k * descriptor_length,
                          descriptors.begin() + (k + 1) * descriptor_length);
    if (checkLandmark(l, descriptor_length, k)) {
      ++*skipped;
      continue;
    }
    out.push_back(std::move(l));
  }
  return out;
}

std::vector<PriorLandmark> toPriorLandmarks(const MapData& map) {
  std::vector<PriorLandmark> out(map.landmarks.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i].position = map.landmarks[i].position;
    out[i].covariance = map.landmarks[i].covariance;
    out[i].times_observed = static_cast<int>(std::min<uint32_t>(map.landmarks[i].times_observed, 1u << 30));
    out[i].descriptor = map.landmarks[i].descriptor;
  }
  return out;
}

}  // namespace map_file
}  // namespace hapi_eskf
