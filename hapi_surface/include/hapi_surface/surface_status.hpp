// Outcome of every core call that takes outside input. Bad input is an
// answer, never an exception, and leaves the state it was given unchanged.
#pragma once

namespace hapi_surface {

enum class SurfaceStatus {
  kOk,
  kUnknownEncoding,   // an image encoding the converter does not know
  kMalformedImage,    // zero size, step shorter than a row, buffer shorter than step * height
  kSizeMismatch,      // depth / confidence / camera sizes differ
  kNoValidDepth,      // no finite depth in [min_depth, max_depth] in the frame
  kNonFiniteValue,    // NaN/inf where a number is required (confidence of a valid pixel)
  kBadCamera,         // intrinsics not finite or not positive
  kBadPose,           // pose not finite or its rotation not orthonormal
  kNoPose,            // no pose for the frame's stamp
  kNoVolume,          // nothing integrated yet
  kVolumeTooLarge,    // the settings ask for more than max_voxels
  kIoError,           // file could not be opened / written
  kParseError,        // file content is not the expected format
  kDeviceError,       // a CUDA call failed (no device, out of memory)
};

// Stable snake_case name (a diagnostics key, a log word).
const char* toString(SurfaceStatus s);

}  // namespace hapi_surface
