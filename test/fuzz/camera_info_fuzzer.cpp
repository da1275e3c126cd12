// libFuzzer target: the left and right sensor_msgs/CameraInfo that
// EskfNodelet hears on ~left/camera_info and ~right/camera_info, through the
// conversion to the calibration a saved map records and a loaded map is
// checked against (ros_glue::toMapCalibration). Input: pairs of records,
// left then right (bounded_message.hpp), up to 4 pairs. A calibration the
// conversion accepts must pass the map's own calibration rule, agree with
// itself, and go into a map file that reads back.
#include "bounded_message.hpp"

#include "hapi_eskf/map_file/map_checks.hpp"
#include "hapi_eskf/map_file/map_reader.hpp"
#include "hapi_eskf/map_file/map_writer.hpp"
#include "hapi_eskf/ros/map_calibration.hpp"

#include <sensor_msgs/CameraInfo.h>

#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hapi_eskf;
  hapi_fuzz::Records records(data, size);
  for (int pair = 0; pair < 4; ++pair) {
    const std::uint8_t* rec[2];
    std::size_t len[2];
    if (!records.next(&rec[0], &len[0]) || !records.next(&rec[1], &len[1])) break;
    sensor_msgs::CameraInfo left, right;
    if (!hapi_fuzz::deserialise<sensor_msgs::CameraInfo_>(rec[0], len[0], &left) ||
        !hapi_fuzz::deserialise<sensor_msgs::CameraInfo_>(rec[1], len[1], &right))
      continue;
    map_file::MapCalibration calibration;
    std::string why;
    if (!ros_glue::toMapCalibration(left, right, &calibration, &why)) {
      if (why.empty()) std::abort();  // a refusal always names its reason
      continue;
    }
    if (map_file::checkCalibration(calibration) || map_file::checkSameCamera(calibration, calibration)) std::abort();
    map_file::MapData map;
    map.map_frame = "map";
    map.calibration = calibration;
    map.descriptor_type = map_file::kDescriptorOrb;
    map.descriptor_length = map_file::descriptorLengthOf(map.descriptor_type);
    map_file::MapError error;
    const std::vector<std::uint8_t> bytes = map_file::encodeMap(map, &error);
    if (error) std::abort();
    map_file::MapExpectation expect;
    expect.calibration = &calibration;
    map_file::MapData back;
    if (map_file::decodeMap(bytes.data(), bytes.size(), expect, &back)) std::abort();
  }
  return 0;
}
