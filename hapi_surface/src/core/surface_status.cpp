#include "hapi_surface/surface_status.hpp"

namespace hapi_surface {

const char* toString(SurfaceStatus s) {
  switch (s) {
    case SurfaceStatus::kOk: return "ok";
    case SurfaceStatus::kUnknownEncoding: return "unknown_encoding";
    case SurfaceStatus::kMalformedImage: return "malformed_image";
    case SurfaceStatus::kSizeMismatch: return "size_mismatch";
    case SurfaceStatus::kNoValidDepth: return "no_valid_depth";
    case SurfaceStatus::kNonFiniteValue: return "non_finite_value";
    case SurfaceStatus::kBadCamera: return "bad_camera";
    case SurfaceStatus::kBadPose: return "bad_pose";
    case SurfaceStatus::kNoPose: return "no_pose";
    case SurfaceStatus::kNoVolume: return "no_volume";
    case SurfaceStatus::kVolumeTooLarge: return "volume_too_large";
    case SurfaceStatus::kIoError: return "io_error";
    case SurfaceStatus::kParseError: return "parse_error";
    case SurfaceStatus::kDeviceError: return "device_error";
  }
  return "?";
}

}  // namespace hapi_surface
