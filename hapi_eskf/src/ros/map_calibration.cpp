// CameraInfo pair -> map calibration (map_calibration.hpp).
#include "hapi_eskf/ros/map_calibration.hpp"

#include "hapi_eskf/map_file/map_checks.hpp"

namespace hapi_eskf {
namespace ros_glue {

bool toMapCalibration(const sensor_msgs::CameraInfo& left, const sensor_msgs::CameraInfo& right,
                      map_file::MapCalibration* out, std::string* why) {
  if (left.width != right.width || left.height != right.height) {
    *why = "left and right camera_info differ in image size";
    return false;
  }
  const double fx = right.P[0];
  const double baseline = fx != 0.0 ? -right.P[3] / fx : 0.0;
  map_file::MapCalibration c;
  c.width = left.width;
  c.height = left.height;
  c.fx = left.P[0];
  c.fy = left.P[5];
  c.cx = left.P[2];
  c.cy = left.P[6];
  c.baseline = baseline;
  if (const map_file::MapError e = map_file::checkCalibration(c)) {
    *why = "camera_info is not a rectified stereo pair (P of left and right, Tx = -fx * baseline in the right's): " +
           e.message;
    return false;
  }
  *out = c;
  return true;
}

}  // namespace ros_glue
}  // namespace hapi_eskf
