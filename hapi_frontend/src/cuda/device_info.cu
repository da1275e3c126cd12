// Device presence probe used by tests (GTEST_SKIP), benchmarks and the
// pipeline's backend selection (hapi_nodelet_kit's probe, shared with the
// other packages' GPU code).
#include "hapi_frontend/cuda/orb_cuda.hpp"

#include <hapi_nodelet_kit/cuda_device_probe.hpp>

namespace hapi_frontend {

bool cudaDeviceAvailable(std::string* info) { return hapi_nodelet_kit::cudaDeviceUsable(info); }

}  // namespace hapi_frontend
