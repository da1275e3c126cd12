// CameraInfo YAML (camera_info.hpp), the layout of camera_calibration_parsers.
#include "hapi_dataset/camera_info.hpp"

#include <cstdio>
#include <sstream>

namespace hapi_dataset {
namespace {

template <typename Values>
void matrix(std::ostringstream& os, const char* name, int rows, int cols, const Values& v) {
  os << name << ":\n  rows: " << rows << "\n  cols: " << cols << "\n  data: [";
  for (size_t i = 0; i < v.size(); ++i) {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%.17g", v[i]);
    os << (i ? ", " : "") << buf;
  }
  os << "]\n";
}

}  // namespace

std::string cameraInfoYaml(const CameraInfoData& info, const std::string& camera_name) {
  std::ostringstream os;
  os << "image_width: " << info.width << "\nimage_height: " << info.height << "\ncamera_name: " << camera_name << "\n";
  matrix(os, "camera_matrix", 3, 3, info.K);
  os << "distortion_model: " << info.distortion_model << "\n";
  matrix(os, "distortion_coefficients", 1, static_cast<int>(info.D.size()), info.D);
  matrix(os, "rectification_matrix", 3, 3, info.R);
  matrix(os, "projection_matrix", 3, 4, info.P);
  return os.str();
}

}  // namespace hapi_dataset
