// The recording tools' command-line parsing (command_line.hpp).
#include "hapi_dataset/command_line.hpp"

#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace hapi_dataset {

void forEachOption(int argc, char** argv, const std::function<void(const std::string&)>& usage,
                   const std::function<void(const std::string& key, const std::string& value)>& handle) {
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    if (k == "-h" || k == "--help") usage("help");
    if (i + 1 >= argc) usage("missing value for " + k);
    try {
      handle(k, argv[++i]);
    } catch (const std::invalid_argument& e) {
      usage(e.what());
    }
  }
}

double parseNumberArg(const std::string& key, const std::string& value) {
  char* end = nullptr;
  const double d = std::strtod(value.c_str(), &end);
  if (value.empty() || *end != '\0' || !std::isfinite(d))
    throw std::invalid_argument("invalid number for " + key + ": '" + value + "'");
  return d;
}

long long parseIntegerArg(const std::string& key, const std::string& value, long long lo, long long hi) {
  const double d = parseNumberArg(key, value);
  if (d < static_cast<double>(lo) || d > static_cast<double>(hi) || d != std::floor(d))
    throw std::invalid_argument(key + " must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return static_cast<long long>(d);
}

bool parseFlagArg(const std::string& key, const std::string& value) {
  if (value != "0" && value != "1") throw std::invalid_argument(key + " must be 0 or 1");
  return value == "1";
}

}  // namespace hapi_dataset
