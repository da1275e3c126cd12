// Where a tool's landmark stream comes from, named by one command-line
// argument: a frames file (landmark_stream.hpp) or the synthetic orbit
// (synthetic_orbit.hpp), so eskf_replay and compare_backends accept the same
// sources and a GPU machine without ROS or bags can still replay long streams.
#pragma once

#include "landmark_stream.hpp"

#include <string>

namespace hapi_eskf {
namespace tools {

// The synthetic form and its options (SyntheticOrbitOptions' fields):
//   --synthetic-orbit[=SEED][,frames=N][,points=N][,max_measurements=N]
extern const char* const kStreamSourceUsage;

// Fills *out from `source`; false with *error on an unreadable file, a
// malformed line or an unknown synthetic option.
bool loadStreamSource(const std::string& source, LandmarkStream* out, std::string* error);

}  // namespace tools
}  // namespace hapi_eskf
