// The TSDF integration of a host volume on a CUDA device: the same
// per-voxel update as the CPU (tsdf_math.hpp), one thread per voxel. The
// volume kept on the device, with its meshing: surface_volume_cuda.hpp.
// Declared without CUDA types so that CPU code can call it; defined only
// where HAPI_SURFACE_WITH_CUDA.
#pragma once

#include "hapi_surface/tsdf_volume.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace hapi_surface {

// Whether a CUDA device is usable; *info = its name or why not.
bool surfaceCudaAvailable(std::string* info);

// Keeps device buffers for one volume size. integrate() uploads the volume,
// runs the kernel and downloads the result, so the host volume stays the
// one the mesh is extracted from (and a rebuild's clear() needs no sync).
class CudaTsdfIntegrator {
 public:
  CudaTsdfIntegrator();
  ~CudaTsdfIntegrator();
  CudaTsdfIntegrator(const CudaTsdfIntegrator&) = delete;
  CudaTsdfIntegrator& operator=(const CudaTsdfIntegrator&) = delete;

  // As TsdfVolume::integrate (same checks, same result); kDeviceError when a
  // CUDA call fails (the host volume is then unchanged).
  SurfaceStatus integrate(TsdfVolume* volume, const DepthFrame& frame);

  // Milliseconds of the last call's kernel alone and of the whole call
  // (transfers included), CUDA events.
  float lastKernelMs() const { return kernel_ms_; }
  float lastTotalMs() const { return total_ms_; }

 private:
  struct Buffers;
  std::unique_ptr<Buffers> buf_;
  float kernel_ms_ = 0, total_ms_ = 0;
};

}  // namespace hapi_surface
