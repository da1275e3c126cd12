// The back-end factory (docs/DESIGN.md "Back ends"): backend_algorithm ->
// implementation. It sits above every algorithm folder and is the one place
// that knows them all; each algorithm plugs in the same way, through its
// maker (backend/slam_backend_maker.hpp).
#pragma once

#include "hapi_eskf/backend/slam_backend.hpp"
#include "hapi_eskf/settings.hpp"
#include "hapi_eskf/types.hpp"

#include <memory>
#include <string>

namespace hapi_eskf {

// The back end named by settings.backend_algorithm. `descriptor_length` is
// the bytes per descriptor of the stream (known from the first frame),
// `extrinsic` the camera in the IMU frame (IMU motion models). nullptr with
// *error when it cannot be created: invalid settings, the ES-EKF's cuda
// storage unavailable, or an algorithm not built into this library.
std::unique_ptr<SlamBackend> makeSlamBackend(const EskfSettings& settings, int descriptor_length,
                                             const CameraExtrinsic& extrinsic, std::string* error);

// Whether makeSlamBackend can build `algorithm` at all in this library (the
// nodelet checks it at start-up); *why says why not.
bool slamBackendBuilt(BackendAlgorithm algorithm, std::string* why);

}  // namespace hapi_eskf
