// libFuzzer target: a saved landmark map (hapi_eskf/map_file) as ~map_file or
// ~load_map reads it. The whole input is the file's bytes. A file the reader
// accepts must be one the writer writes again, and reading that back must
// give the same map (the reader's and the writer's rules are one copy).
#include "hapi_eskf/map_file/map_reader.hpp"
#include "hapi_eskf/map_file/map_writer.hpp"

#include <cstdlib>

namespace {

bool same(const hapi_eskf::map_file::MapData& a, const hapi_eskf::map_file::MapData& b) {
  if (a.landmarks.size() != b.landmarks.size() || a.map_frame != b.map_frame || a.camera_frame != b.camera_frame ||
      a.descriptor_type != b.descriptor_type)
    return false;
  for (std::size_t i = 0; i < a.landmarks.size(); ++i) {
    const auto& x = a.landmarks[i];
    const auto& y = b.landmarks[i];
    if (x.id != y.id || x.position != y.position || x.covariance != y.covariance || x.descriptor != y.descriptor)
      return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hapi_eskf::map_file;
  MapData map;
  if (decodeMap(data, size, {}, &map)) return 0;
  // Against another running camera: must be refused.
  MapCalibration running = map.calibration;
  running.width += 1;
  MapExpectation expect;
  expect.descriptor_type = kDescriptorOrb;
  expect.calibration = &running;
  MapData unused;
  if (!decodeMap(data, size, expect, &unused)) std::abort();
  MapError error;
  const std::vector<std::uint8_t> again = encodeMap(map, &error);
  if (error) std::abort();
  MapData back;
  if (decodeMap(again.data(), again.size(), {}, &back) || !same(map, back)) std::abort();
  return 0;
}
