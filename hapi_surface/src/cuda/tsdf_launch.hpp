// The TSDF integration kernel's launch (tsdf_cuda.cu), shared by the
// integrator that round-trips a host volume and the device-resident volume.
#pragma once

#include "hapi_surface/tsdf_math.hpp"

namespace hapi_surface {

// One thread per voxel of p.dims, updateVoxel() (tsdf_math.hpp) on device
// buffers; weight may be nullptr (1 per pixel). False when the launch fails.
bool launchIntegrate(const TsdfIntegrationParams& p, const float* depth, const float* weight, float* tsdf,
                     float* voxel_weight);

}  // namespace hapi_surface
