// Time per keyframe of the surface core at the default settings: a 20 x 10 x
// 4 cm volume at 0.5 mm voxels (400 x 200 x 80 = 6.4 M voxels) over a skin-
// like patch (a 15 cm radius sphere) scanned at 25 cm by a 640 x 480
// camera. Per keyframe: CPU integration, meshing, one imaging-frame
// projection; where a device is present, the CUDA integration of a host
// volume (kernel alone, and with the volume's transfers), and the volume
// resident on the device (CudaSurfaceVolume): its integration (the depth's
// upload and the kernel) and its meshing (the mesh's download included),
// whose faces are checked against the CPU's, into one mesh reused. Prints,
// asserts nothing.
//   hapi_surface_bench [keyframes=8]
#include "hapi_surface/mesh_extraction.hpp"
#include "hapi_surface/surface_values.hpp"
#ifdef HAPI_SURFACE_WITH_CUDA
#include "hapi_surface/cuda/surface_volume_cuda.hpp"
#endif

#include "synthetic_scene.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>

namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  using namespace hapi_surface;
  const int keyframes = argc > 1 ? std::atoi(argv[1]) : 8;
  const SurfaceSettings s;
  // The skin: a sphere of radius 15 cm whose top is at z = 0.25.
  const Eigen::Vector3d top(0, 0, 0.25);
  test::Scene scene;
  scene.addSphere(Eigen::Vector3d(0, 0, 0.40), 0.15);
  const VoxelGrid grid = VoxelGrid::centredAt(top + Eigen::Vector3d(0, 0, 0.01), s);
  TsdfVolume cpu(grid, s);
  SurfaceValues values(grid.size());
  std::printf("volume %d x %d x %d = %.2f M voxels of %.2f mm\n", grid.dims.x(), grid.dims.y(), grid.dims.z(),
              grid.size() / 1e6, s.voxel_size * 1e3);
#ifdef HAPI_SURFACE_WITH_CUDA
  std::string info;
  const bool gpu = surfaceCudaAvailable(&info);
  std::printf("CUDA: %s\n", info.c_str());
  TsdfVolume on_gpu(grid, s);
  CudaSurfaceVolume cuda;  // a host volume's round trip
  CudaSurfaceVolume resident;
  const bool resident_ok = gpu && resident.upload(TsdfVolume(grid, s)) == SurfaceStatus::kOk;
  Mesh on_device;  // reused, as a node that keeps its mesh does
#else
  std::printf("CUDA: not built\n");
#endif
  std::printf("%3s %12s %10s %10s %8s %8s %12s %12s %12s %12s %12s %12s\n", "kf", "integrate_ms", "mesh_ms", "project_ms",
              "faces", "values", "gpu_kernel", "gpu_total", "res_int_ms", "res_mesh_ms", "res_mesh_krn", "res_sum_ms");
  for (int k = 0; k < keyframes; ++k) {
    DepthFrame f;
    f.camera = test::testCamera();
    const double x = -0.08 + 0.16 * k / std::max(1, keyframes - 1);
    f.T_world_camera = test::lookAt(Eigen::Vector3d(x, 0.01 * (k % 3), 0), Eigen::Vector3d(x, 0, 0.25));
    f.depth = scene.depth(f.camera, f.T_world_camera);
    auto t0 = std::chrono::steady_clock::now();
    cpu.integrate(f);
    const double t_int = msSince(t0);
    t0 = std::chrono::steady_clock::now();
    const Mesh mesh = extractMesh(cpu);
    const double t_mesh = msSince(t0);
    const FloatImage image = scene.pattern(f.camera, f.T_world_camera, [](const Eigen::Vector3d& p) { return p.x(); });
    t0 = std::chrono::steady_clock::now();
    const ProjectionResult r = values.addFrame(cpu, mesh, image, f.camera, f.T_world_camera);
    const double t_proj = msSince(t0);
    double g_kernel = -1, g_total = -1, r_int = -1, r_mesh = -1, r_mesh_kernels = -1;
#ifdef HAPI_SURFACE_WITH_CUDA
    if (gpu && cuda.integrateHost(&on_gpu, f) == SurfaceStatus::kOk) {
      g_kernel = cuda.lastIntegrateKernelMs();
      g_total = cuda.lastRoundTripMs();
    }
    if (resident_ok && resident.integrate(f) == SurfaceStatus::kOk &&
        resident.extractMesh(&on_device) == SurfaceStatus::kOk) {
      r_int = resident.lastIntegrateMs();
      r_mesh = resident.lastMeshMs();
      r_mesh_kernels = resident.lastMeshKernelsMs();
      if (on_device.faces.size() != mesh.faces.size() || on_device.vertices.size() != mesh.vertices.size())
        std::printf("the device's mesh differs: %zu faces, %zu vertices\n", on_device.faces.size(),
                    on_device.vertices.size());
    }
#endif
    std::printf("%3d %12.1f %10.1f %10.1f %8zu %8zu %12.3f %12.3f %12.3f %12.3f %12.3f %12.3f\n", k, t_int, t_mesh,
                t_proj, mesh.faces.size(), r.voxels_updated, g_kernel, g_total, r_int, r_mesh, r_mesh_kernels,
                r_int >= 0 ? r_int + r_mesh : -1.0);
  }
  return 0;
}
