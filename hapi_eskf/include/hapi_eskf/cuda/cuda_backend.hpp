// Entry points of the CUDA backend (src/cuda). Declared here so the ROS-free
// factory can call them when HAPI_ESKF_WITH_CUDA is defined; the header itself
// has no CUDA dependency.
#pragma once

#include "hapi_eskf/covariance_backend.hpp"

namespace hapi_eskf {
namespace cuda {

// nullptr and *error on failure (no device, out of memory ...).
std::unique_ptr<CovarianceBackend> makeCudaBackend(int capacity, int descriptor_length, Precision precision,
                                                   int device, std::string* error);
// Device usable? Name + memory in *info, reason in *info otherwise.
bool deviceAvailable(int device, std::string* info);

}  // namespace cuda
}  // namespace hapi_eskf
