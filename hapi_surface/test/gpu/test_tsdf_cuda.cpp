// The CUDA TSDF integration of a host volume gives the CPU's volume (same
// per-voxel update, tsdf_math.hpp, no FMA either side): weights equal, TSDF
// values equal to the last bit, over several frames with and without
// per-pixel weights. The device-resident volume integrates and meshes as
// the CPU does, to the last bit.
#include "hapi_surface/cuda/surface_volume_cuda.hpp"
#include "hapi_surface/mesh_extraction.hpp"

#include "hapi_test/skip.hpp"
#include "synthetic_scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <unordered_map>

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
  CudaSurfaceVolume cuda;
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
    ASSERT_EQ(cuda.integrateHost(&gpu, f), SurfaceStatus::kOk);
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
  CudaSurfaceVolume cuda;
  EXPECT_EQ(cuda.integrateHost(&v, f), SurfaceStatus::kSizeMismatch);
  EXPECT_EQ(v.observedVoxels(), 0u);
}

// A vertex is named by its grid edge: the CPU numbers vertices by first
// use, the GPU by edge.
std::uint64_t edgeKey(const Mesh& m, std::int32_t v) {
  return (static_cast<std::uint64_t>(m.vertex_edges[v][0]) << 32) | m.vertex_edges[v][1];
}

TEST(TsdfCuda, ResidentVolumeIntegratesAndMeshesAsTheCpu) {
  std::string info;
  if (!surfaceCudaAvailable(&info)) HAPI_SKIP_WITHOUT_GPU("no CUDA device: " + info);
  const SurfaceSettings s = test::volumeOf(0.06, 0.06, 0.03);
  const Eigen::Vector3d c(0, 0, 0.25);
  test::Scene scene;
  scene.addSphere(c + Eigen::Vector3d(0, 0, 0.01), 0.02);
  scene.addPlane(Eigen::Vector3d(0.1, 0, 1).normalized(), 0.262);
  const VoxelGrid grid = VoxelGrid::centredAt(c, s);
  TsdfVolume cpu(grid, s), back(grid, s);
  CudaSurfaceVolume gpu;
  Mesh m;
  EXPECT_EQ(gpu.extractMesh(&m), SurfaceStatus::kNoVolume);
  ASSERT_EQ(gpu.upload(cpu), SurfaceStatus::kOk);
  ASSERT_EQ(gpu.extractMesh(&m), SurfaceStatus::kOk);
  EXPECT_TRUE(m.empty());  // never observed: no surface
  for (int i = 0; i < 4; ++i) {
    DepthFrame f;
    f.camera = test::testCamera();
    f.T_world_camera = test::lookAt(Eigen::Vector3d(0.01 * i, 0.005 * i, 0), c);
    f.depth = scene.depth(f.camera, f.T_world_camera);
    if (i % 2 == 1) {
      f.weight = f.depth;
      for (std::size_t p = 0; p < f.weight.data.size(); ++p) f.weight.data[p] = 0.5f + (p % 7) * 0.25f;
    }
    ASSERT_EQ(cpu.integrate(f), SurfaceStatus::kOk);
    ASSERT_EQ(gpu.integrate(f), SurfaceStatus::kOk);
  }
  ASSERT_EQ(gpu.download(&back), SurfaceStatus::kOk);
  EXPECT_EQ(back.tsdf(), cpu.tsdf());
  EXPECT_EQ(back.weight(), cpu.weight());

  const Mesh a = extractMesh(cpu);
  ASSERT_EQ(gpu.extractMesh(&m), SurfaceStatus::kOk);
  std::printf("%zu faces, %zu vertices (CPU); %zu, %zu (GPU); %.3f ms\n", a.faces.size(), a.vertices.size(),
              m.faces.size(), m.vertices.size(), gpu.lastMeshMs());
  ASSERT_GT(a.faces.size(), 1000u);
  ASSERT_EQ(m.faces.size(), a.faces.size());
  ASSERT_EQ(m.vertices.size(), a.vertices.size());
  std::unordered_map<std::uint64_t, std::int32_t> cpu_vertex;
  for (std::size_t v = 0; v < a.vertices.size(); ++v) cpu_vertex[edgeKey(a, static_cast<std::int32_t>(v))] = v;
  std::size_t vertices_differ = 0, faces_differ = 0;
  for (std::size_t v = 0; v < m.vertices.size(); ++v) {
    const auto it = cpu_vertex.find(edgeKey(m, static_cast<std::int32_t>(v)));
    if (it == cpu_vertex.end() || std::memcmp(m.vertices[v].data(), a.vertices[it->second].data(), 12) != 0 ||
        std::memcmp(m.normals[v].data(), a.normals[it->second].data(), 12) != 0 ||
        m.vertex_t[v] != a.vertex_t[it->second])
      ++vertices_differ;
  }
  for (std::size_t f = 0; f < a.faces.size(); ++f)
    for (int e = 0; e < 3; ++e)
      if (edgeKey(m, m.faces[f][e]) != edgeKey(a, a.faces[f][e])) {
        ++faces_differ;
        break;
      }
  EXPECT_EQ(vertices_differ, 0u);
  EXPECT_EQ(faces_differ, 0u);

  // A bad frame changes nothing on the device either.
  DepthFrame bad;
  bad.camera = test::testCamera();
  bad.depth.width = 10;
  bad.depth.height = 10;
  bad.depth.data.assign(100, 0.25f);
  EXPECT_EQ(gpu.integrate(bad), SurfaceStatus::kSizeMismatch);
  TsdfVolume again(grid, s);
  ASSERT_EQ(gpu.download(&again), SurfaceStatus::kOk);
  EXPECT_EQ(again.tsdf(), cpu.tsdf());
  TsdfVolume other(VoxelGrid::centredAt(c, test::volumeOf(0.02, 0.02, 0.02)), s);
  EXPECT_EQ(gpu.download(&other), SurfaceStatus::kSizeMismatch);
}

}  // namespace
}  // namespace hapi_surface
