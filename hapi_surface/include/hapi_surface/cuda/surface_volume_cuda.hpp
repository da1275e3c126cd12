// A TSDF volume resident on a CUDA device (docs/DESIGN.md "Surface", GPU):
// depth frames go up, the mesh comes down, and the volume stays there.
// Integration is updateVoxel() (tsdf_math.hpp) and meshing the marching
// tetrahedra of extractMesh() (marching_tetrahedra.hpp), so the volume is
// the CPU's to the last bit and the mesh is the CPU's: the same vertices
// (position, normal, edge, t) and the same faces in the same order, only
// the vertices numbered in another order (by grid edge, not by first use).
// Declared without CUDA types so that CPU code can call it; defined only
// where HAPI_SURFACE_WITH_CUDA.
#pragma once

#include "hapi_surface/mesh.hpp"
#include "hapi_surface/tsdf_volume.hpp"

#include <memory>
#include <string>

namespace hapi_surface {

// Whether a CUDA device is usable; *info = its name or why not.
bool surfaceCudaAvailable(std::string* info);

class CudaSurfaceVolume {
 public:
  CudaSurfaceVolume();
  ~CudaSurfaceVolume();
  CudaSurfaceVolume(const CudaSurfaceVolume&) = delete;
  CudaSurfaceVolume& operator=(const CudaSurfaceVolume&) = delete;

  // Takes the volume's grid, settings and values. kDeviceError when a CUDA
  // call fails (the device volume is then unusable until the next upload).
  SurfaceStatus upload(const TsdfVolume& volume);
  // As TsdfVolume::integrate on the device volume (same checks, same bits).
  // kNoVolume before an upload.
  SurfaceStatus integrate(const DepthFrame& frame);
  // The device volume's values into *volume, which must have its grid
  // (kSizeMismatch otherwise; *volume is unchanged on any error).
  SurfaceStatus download(TsdfVolume* volume) const;
  // TsdfVolume::integrate of a host volume on the device (same checks, same
  // bits): upload, integrate, download. kDeviceError when a CUDA call fails;
  // *volume changes only on success.
  SurfaceStatus integrateHost(TsdfVolume* volume, const DepthFrame& frame);
  // extractMesh() of the device volume into *mesh, whose memory is reused
  // (pass the same mesh again to avoid the page faults of a fresh one); on
  // an error *mesh is empty.
  SurfaceStatus extractMesh(Mesh* mesh);

  // Milliseconds of the last integrate() (depth upload and kernel) and of
  // its kernel alone, of the last integrateHost() (the volume's upload and
  // download included, wall clock), of the last extractMesh() (kernels,
  // scans and the mesh's download into *mesh) and of its kernels and scans
  // alone; CUDA events unless said.
  float lastIntegrateMs() const { return integrate_ms_; }
  float lastIntegrateKernelMs() const { return integrate_kernel_ms_; }
  float lastRoundTripMs() const { return round_trip_ms_; }
  float lastMeshMs() const { return mesh_ms_; }
  float lastMeshKernelsMs() const { return mesh_kernels_ms_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  float integrate_ms_ = 0, integrate_kernel_ms_ = 0, round_trip_ms_ = 0, mesh_ms_ = 0, mesh_kernels_ms_ = 0;
};

}  // namespace hapi_surface
