// Names of the map file's faults (map_error.hpp).
#include "hapi_eskf/map_file/map_error.hpp"

namespace hapi_eskf {
namespace map_file {

const char* faultName(MapFault fault) {
  switch (fault) {
    case MapFault::kNone: return "ok";
    case MapFault::kIo: return "io";
    case MapFault::kTruncated: return "truncated";
    case MapFault::kMagic: return "magic";
    case MapFault::kVersion: return "version";
    case MapFault::kSectionTable: return "section_table";
    case MapFault::kMissingSection: return "missing_section";
    case MapFault::kBadSize: return "bad_size";
    case MapFault::kUnit: return "unit";
    case MapFault::kDescriptorType: return "descriptor_type";
    case MapFault::kCalibrationMismatch: return "calibration_mismatch";
    case MapFault::kNotFinite: return "not_finite";
    case MapFault::kCovarianceNotPd: return "covariance_not_pd";
    case MapFault::kBadValue: return "bad_value";
  }
  return "unknown";
}

MapError mapError(MapFault fault, const std::string& what) {
  return MapError{fault, std::string(faultName(fault)) + ": " + what};
}

}  // namespace map_file
}  // namespace hapi_eskf
