// What is wrong with a map file: one code per kind of fault, with a message
// naming the field (the reader loads nothing when it returns one).
#pragma once

#include <string>

namespace hapi_eskf {
namespace map_file {

enum class MapFault {
  kNone,
  kIo,                   // cannot open, read or write the file
  kTruncated,            // the bytes end before a header, table entry or field
  kMagic,                // not a HAPI map file
  kVersion,              // another format version
  kSectionTable,         // section count, bounds, overlap, duplicate or unknown required section
  kMissingSection,       // a required section is absent
  kBadSize,              // a section's size disagrees with its content
  kUnit,                 // a length unit other than metres
  kDescriptorType,       // unknown type, wrong length, or not the running front end's
  kCalibrationMismatch,  // made with another camera than the running one
  kNotFinite,            // NaN or infinity in a number
  kCovarianceNotPd,      // a landmark covariance not symmetric positive definite
  kBadValue,             // any other value out of range (id, count, name, gravity, calibration)
};

const char* faultName(MapFault fault);

struct MapError {
  MapFault fault = MapFault::kNone;
  std::string message;  // "<fault name>: <what and where>"
  explicit operator bool() const { return fault != MapFault::kNone; }
};

MapError mapError(MapFault fault, const std::string& what);

}  // namespace map_file
}  // namespace hapi_eskf
