// The CUDA TSDF integration gives the CPU's volume (same per-voxel update,
// tsdf_math.hpp, no FMA either side): weights equal, TSDF values equal to
// the last bit, over several frames with and without per-pixel weights. The
// GPU's active cells give the CPU's mesh.
#include "hapi_surface/cuda/tsdf_cuda.hpp"
#include "hapi_surface/mesh_extraction.hpp"

#include "hapi_test/skip.hpp"
#include "synthetic_scene.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace hapi_surface {
namespace {

TEST(TsdfCuda, SameVolumeAsCpu) {
  std::string info;
  if (!surfaceCudaAvailable(&info)) HAPI_SKIP_WITHOUT_GPU("no CUDA device: " + info);
  std::printf("device: %s\n", info.c_str());
  const SurfaceSettings s = test::volumeOf(0.06, 0.06, 0.03);
  const Eigen::Vector3d c(0, 0, 0.25);
  test::Scene scene;
  scene.addSphere(c + Eigen::Vector3d(0, 0, 0.01), 0.02);
  scene.addPlane(Eigen::Vector3d(0.1, 0, 1).normalized(), 0.262);
  TsdfVolume cpu(VoxelGrid::centredAt(c, s), s), gpu(VoxelGrid::centredAt(c, s), s);
  CudaTsdfIntegrator cuda;
  for (int i = 0; i < 4; ++i) {
    DepthFrame f;
    f.camera = test::testCamera();
    f.T_world_camera = test::lookAt(Eigen::Vector3d(0.01 * i, 0.005 * i, 0), c);
    f.depth = scene.depth(f.camera, f.T_world_camera);
    if (i % 2 == 1) {  // per-pixel weights on every other frame
      f.weight = f.depth;
      for (std::size_t p = 0; p < f.weight.data.size(); ++p) f.weight.data[p] = 0.5f + (p % 7) * 0.25f;
    }
    ASSERT_EQ(cpu.integrate(f), SurfaceStatus::kOk);
    ASSERT_EQ(cuda.integrate(&gpu, f), SurfaceStatus::kOk);
  }
  std::size_t differ = 0;
  float worst = 0;
  for (std::size_t i = 0; i < cpu.tsdf().size(); ++i) {
    if (cpu.weight()[i] != gpu.weight()[i] || cpu.tsdf()[i] != gpu.tsdf()[i]) ++differ;
    worst = std::max(worst, std::abs(cpu.tsdf()[i] - gpu.tsdf()[i]));
  }
  std::printf("%zu voxels, %zu observed, %zu differ, largest TSDF difference %g\n", cpu.tsdf().size(),
              cpu.observedVoxels(), differ, worst);
  EXPECT_GT(cpu.observedVoxels(), 100000u);
  EXPECT_EQ(differ, 0u);

  // Meshing with the GPU's active cells: the same mesh.
  CudaActiveCells cells;
  std::vector<std::uint8_t> active;
  ASSERT_EQ(cells.find(gpu, &active), SurfaceStatus::kOk);
  std::size_t n_active = 0;
  for (std::uint8_t a : active) n_active += a;
  const Mesh a = extractMesh(gpu), b = extractMesh(gpu, &active);
  std::printf("%zu active cells, %zu faces\n", n_active, a.faces.size());
  EXPECT_GT(n_active, 1000u);
  EXPECT_LT(n_active, active.size() / 10);
  ASSERT_GT(a.faces.size(), 1000u);
  EXPECT_EQ(a.faces, b.faces);
  EXPECT_EQ(a.vertices, b.vertices);
}

TEST(TsdfCuda, BadFrameChangesNothing) {
  std::string info;
  if (!surfaceCudaAvailable(&info)) HAPI_SKIP_WITHOUT_GPU("no CUDA device: " + info);
  const SurfaceSettings s = test::volumeOf(0.02, 0.02, 0.02);
  TsdfVolume v(VoxelGrid::centredAt(Eigen::Vector3d(0, 0, 0.25), s), s);
  DepthFrame f;
  f.camera = test::testCamera();
  f.depth.width = 10;
  f.depth.height = 10;
  f.depth.data.assign(100, 0.25f);
  CudaTsdfIntegrator cuda;
  EXPECT_EQ(cuda.integrate(&v, f), SurfaceStatus::kSizeMismatch);
  EXPECT_EQ(v.observedVoxels(), 0u);
}

}  // namespace
}  // namespace hapi_surface
