// The binary layout of the map file (docs/DESIGN.md "Map file"), shared by
// the writer and the reader: little-endian, a header (magic, version,
// section count), a section table, then the sections' payloads.
#pragma once

#include <cstdint>

namespace hapi_eskf {
namespace map_file {

constexpr char kMagic[8] = {'H', 'A', 'P', 'I', 'M', 'A', 'P', '\0'};
constexpr uint32_t kVersion = 1;
constexpr uint32_t kHeaderBytes = 16;        // magic, version, section count
constexpr uint32_t kSectionEntryBytes = 24;  // type, flags, offset (u64), size (u64)
constexpr uint32_t kMaxSections = 64;
constexpr uint32_t kMaxNameBytes = 256;      // frame names
constexpr uint8_t kUnitMetre = 0;            // the only length unit written

// Section types. A reader skips a section type it does not know unless its
// kSectionRequired flag is set (then the file is refused), so later versions
// can add keyframes or a surface that older readers may ignore.
enum SectionType : uint32_t {
  kSectionMeta = 1,         // units, frame names, gravity direction, creation time
  kSectionCalibration = 2,  // MapCalibration
  kSectionLandmarks = 3,    // descriptor type/length, the landmarks
  kSectionKeyframes = 4,    // optional: keyframes (pose, covariance, points, descriptors)
  kSectionSurface = 5,      // reserved: a surface mesh in the map frame
};
constexpr uint32_t kSectionRequired = 1u;

// Bytes of one landmark record before its descriptor: id, position (3 f64),
// upper triangle of the covariance (6 f64: xx xy xz yy yz zz), times observed.
constexpr uint32_t kLandmarkFixedBytes = 8 + 3 * 8 + 6 * 8 + 4;
// Bytes of one keyframe record before its points: id, stamp, R_map_cam (9
// f64, row-major), p_map_cam (3 f64), upper triangle of the 6 x 6 pose
// covariance (21 f64), point count (u32).
constexpr uint32_t kKeyframeFixedBytes = 8 + 8 + 9 * 8 + 3 * 8 + 21 * 8 + 4;
// Bytes of one keyframe point before its descriptor: position in the camera
// frame (3 f64), upper triangle of its covariance (6 f64).
constexpr uint32_t kKeyframePointFixedBytes = 3 * 8 + 6 * 8;

}  // namespace map_file
}  // namespace hapi_eskf
