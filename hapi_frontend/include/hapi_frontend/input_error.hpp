// A rejected input, as the front end reports it: a short machine-readable
// reason (a diagnostics counter key) and a detail for the log. ROS-free.
#pragma once

#include <string>

namespace hapi_frontend {

struct InputError {
  std::string reason;  // empty = no error
  std::string detail;
  explicit operator bool() const { return !reason.empty(); }
};

}  // namespace hapi_frontend
