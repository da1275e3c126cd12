// Tool stream sources (stream_source.hpp).
#include "stream_source.hpp"
#include "synthetic_orbit.hpp"

#include <sstream>

namespace hapi_eskf {
namespace tools {

const char* const kStreamSourceUsage =
    "FRAMES.txt|--synthetic-orbit[=SEED][,frames=N][,points=N][,max_measurements=N]";

namespace {

constexpr const char kSynthetic[] = "--synthetic-orbit";

// "SEED", "frames=N", ... after the '=' of --synthetic-orbit=, comma separated.
bool parseSyntheticOptions(const std::string& spec, SyntheticOrbitOptions* o, std::string* error) {
  std::stringstream ss(spec);
  std::string item;
  bool first = true;
  while (std::getline(ss, item, ',')) {
    const auto eq = item.find('=');
    try {
      if (eq == std::string::npos && first) {
        o->seed = static_cast<unsigned>(std::stoul(item));
      } else if (eq != std::string::npos) {
        const std::string key = item.substr(0, eq);
        const int value = std::stoi(item.substr(eq + 1));
        if (value < 1) throw std::invalid_argument(key);
        if (key == "frames") o->frames = value;
        else if (key == "points") o->points = value;
        else if (key == "max_measurements") o->max_measurements = value;
        else throw std::invalid_argument(key);
      } else {
        throw std::invalid_argument(item);
      }
    } catch (const std::exception&) {
      *error = std::string("bad synthetic orbit option '") + item + "' (" + kStreamSourceUsage + ")";
      return false;
    }
    first = false;
  }
  return true;
}

}  // namespace

bool loadStreamSource(const std::string& source, LandmarkStream* out, std::string* error) {
  if (source.rfind(kSynthetic, 0) != 0) return readLandmarkStream(source, out, error);
  std::string rest = source.substr(sizeof(kSynthetic) - 1);
  if (!rest.empty() && rest[0] != '=') {
    *error = "unknown source " + source + " (" + kStreamSourceUsage + ")";
    return false;
  }
  SyntheticOrbitOptions o;
  if (!rest.empty() && !parseSyntheticOptions(rest.substr(1), &o, error)) return false;
  *out = makeSyntheticOrbit(o);
  return true;
}

}  // namespace tools
}  // namespace hapi_eskf
