// CudaSurfaceVolume (surface_volume_cuda.hpp): the resident volume, its
// integration and its marching tetrahedra in four passes (docs/DESIGN.md
// "Surface", GPU): count each cube's triangles and mark the grid edges that
// carry a vertex; prefix sums number the vertices (by edge) and place each
// cube's triangles (in cube order, as the CPU's loop); one thread per marked
// edge writes its vertex; one thread per cube writes its triangles.
#include "hapi_surface/cuda/surface_volume_cuda.hpp"

#include "device_buffer.cuh"
#include "tsdf_launch.hpp"

#include "hapi_surface/marching_tetrahedra.hpp"

#include <cub/device/device_scan.cuh>
#include <cuda_runtime.h>
#include <hapi_nodelet_kit/cuda_device_probe.hpp>

#include <chrono>
#include <cstdint>

namespace hapi_surface {
namespace {

constexpr int kEdgesPerPoint = 7;  // edgeDirection()'s directions

struct GridShape {
  int nx, ny, nz;
  CubeOffsets off;
  double origin[3];
  double voxel;
};

__device__ bool cubeOf(const GridShape& s, int* i, int* j, int* k, unsigned int* g) {
  *i = blockIdx.x * blockDim.x + threadIdx.x;
  *j = blockIdx.y * blockDim.y + threadIdx.y;
  *k = blockIdx.z;
  if (*i >= s.nx || *j >= s.ny) return false;
  *g = (static_cast<unsigned int>(*k) * s.ny + *j) * static_cast<unsigned int>(s.nx) + *i;
  return true;
}

// The edge slot of corner pair (a, b) of the cube at g.
__device__ unsigned int edgeSlot(const GridShape& s, unsigned int g, int a, int b) {
  int lower = 0;
  const int dir = edgeDirection(a, b, &lower);
  return (g + s.off.o[lower]) * kEdgesPerPoint + static_cast<unsigned int>(dir);
}

// Pass 1: triangles per cube, and a 1 on every edge one of them uses.
__global__ void countKernel(GridShape s, const float* tsdf, const float* weight, float min_weight,
                            std::uint32_t* tri_count, std::uint32_t* edge_used) {
  int i, j, k;
  unsigned int g;
  if (!cubeOf(s, &i, &j, &k, &g)) return;
  std::uint32_t n = 0;
  if (i + 1 < s.nx && j + 1 < s.ny && k + 1 < s.nz && cubeActive(tsdf, weight, g, s.off, min_weight)) {
    float f[8];
    for (int c = 0; c < 8; ++c) f[c] = tsdf[g + s.off.o[c]];
    TetTriangles tt;
    for (int t = 0; t < 6; ++t) {
      const int m = tetrahedronTriangles(t, f, &tt);
      for (int q = 0; q < m; ++q)
        for (int e = 0; e < 3; ++e) edge_used[edgeSlot(s, g, tt.edge[q][e][0], tt.edge[q][e][1])] = 1;
      n += static_cast<std::uint32_t>(m);
    }
  }
  tri_count[g] = n;
}

// Pass 3: the vertex of every used edge, at its number.
__global__ void vertexKernel(GridShape s, std::size_t n_slots, const float* tsdf, const float* weight,
                             const std::uint32_t* edge_used, const std::uint32_t* vertex_id, float* pos,
                             float* normal, float* t_out, std::uint32_t* edge_ends) {
  const std::size_t e = static_cast<std::size_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (e >= n_slots || !edge_used[e]) return;
  const unsigned int g = static_cast<unsigned int>(e / kEdgesPerPoint);
  const int d = static_cast<int>(e % kEdgesPerPoint) + 1;
  const int dx = d & 1, dy = (d >> 1) & 1, dz = (d >> 2) & 1;
  const int i = static_cast<int>(g % s.nx), j = static_cast<int>((g / s.nx) % s.ny),
            k = static_cast<int>(g / (static_cast<unsigned int>(s.nx) * s.ny));
  const unsigned int gb = g + dx + dy * s.nx + dz * static_cast<unsigned int>(s.nx) * s.ny;
  float pa[3], pb[3], na[3], nb[3];
  gridPointPosition(s.origin, s.voxel, i, j, k, pa);
  gridPointPosition(s.origin, s.voxel, i + dx, j + dy, k + dz, pb);
  tsdfGradient(tsdf, weight, s.nx, s.ny, s.nz, i, j, k, na);
  tsdfGradient(tsdf, weight, s.nx, s.ny, s.nz, i + dx, j + dy, k + dz, nb);
  const std::uint32_t id = vertex_id[e];
  edgeVertex(pa, pb, tsdf[g], tsdf[gb], na, nb, pos + 3 * id, normal + 3 * id, t_out + id);
  edge_ends[2 * id] = g;
  edge_ends[2 * id + 1] = gb;
}

// Pass 4: each cube's triangles at its place, wound as the CPU winds them.
__global__ void faceKernel(GridShape s, const float* tsdf, const std::uint32_t* tri_count,
                           const std::uint32_t* tri_offset, const std::uint32_t* vertex_id, const float* pos,
                           const float* normal, std::int32_t* faces) {
  int i, j, k;
  unsigned int g;
  if (!cubeOf(s, &i, &j, &k, &g) || tri_count[g] == 0) return;
  float f[8];
  for (int c = 0; c < 8; ++c) f[c] = tsdf[g + s.off.o[c]];
  std::uint32_t out = tri_offset[g];
  TetTriangles tt;
  for (int t = 0; t < 6; ++t) {
    const int m = tetrahedronTriangles(t, f, &tt);
    for (int q = 0; q < m; ++q, ++out) {
      std::int32_t v[3];
      for (int e = 0; e < 3; ++e)
        v[e] = static_cast<std::int32_t>(vertex_id[edgeSlot(s, g, tt.edge[q][e][0], tt.edge[q][e][1])]);
      const bool keep = windingAgreesWithNormals(pos + 3 * v[0], pos + 3 * v[1], pos + 3 * v[2], normal + 3 * v[0],
                                                 normal + 3 * v[1], normal + 3 * v[2]);
      faces[3 * out] = v[0];
      faces[3 * out + 1] = keep ? v[1] : v[2];
      faces[3 * out + 2] = keep ? v[2] : v[1];
    }
  }
}

GridShape shapeOf(const VoxelGrid& g) {
  GridShape s;
  s.nx = g.dims.x();
  s.ny = g.dims.y();
  s.nz = g.dims.z();
  s.off = cubeOffsets(static_cast<unsigned int>(s.nx), static_cast<unsigned int>(s.ny));
  for (int a = 0; a < 3; ++a) s.origin[a] = g.origin[a];
  s.voxel = g.voxel;
  return s;
}

template <typename T>
bool download(std::vector<T>* out, const void* src, std::size_t n) {
  out->resize(n);
  return n == 0 || cudaMemcpy(out->data(), src, n * sizeof(T), cudaMemcpyDeviceToHost) == cudaSuccess;
}

static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float), "mesh vertices are copied as packed floats");
static_assert(sizeof(std::array<std::int32_t, 3>) == 3 * sizeof(std::int32_t), "faces are copied as packed ints");
static_assert(sizeof(std::array<std::uint32_t, 2>) == 2 * sizeof(std::uint32_t), "edges are copied packed");

}  // namespace

struct CudaSurfaceVolume::Impl {
  bool loaded = false;  // an upload succeeded: grid, settings and the device values hold
  VoxelGrid grid;
  SurfaceSettings settings;
  DeviceFloats tsdf, weight, depth, pixel_weight;
  DeviceBuffer<std::uint32_t> tri_count, tri_offset, edge_used, vertex_id, edge_ends;
  DeviceFloats pos, normal, t;
  DeviceBuffer<std::int32_t> faces;
  DeviceBuffer<std::uint8_t> scan_temp;
  cudaEvent_t start = nullptr, kernel_start = nullptr, kernels_end = nullptr, end = nullptr;
  Impl() {
    cudaEventCreate(&start);
    cudaEventCreate(&kernel_start);
    cudaEventCreate(&kernels_end);
    cudaEventCreate(&end);
  }
  ~Impl() {
    cudaEventDestroy(start);
    cudaEventDestroy(kernel_start);
    cudaEventDestroy(kernels_end);
    cudaEventDestroy(end);
  }
  // The mesh's n_vtx vertices and n_tri faces into *out, reusing its
  // vectors' memory: a mesh's 20 MB written into fresh pages costs more in
  // page faults than the copy itself (docs/BENCHMARKS.md "Surface").
  bool downloadMesh(std::size_t n_vtx, std::size_t n_tri, Mesh* out) {
    return hapi_surface::download(&out->vertices, pos.ptr, n_vtx) &&
           hapi_surface::download(&out->normals, normal.ptr, n_vtx) &&
           hapi_surface::download(&out->vertex_t, t.ptr, n_vtx) &&
           hapi_surface::download(&out->vertex_edges, edge_ends.ptr, n_vtx) &&
           hapi_surface::download(&out->faces, faces.ptr, n_tri);
  }

  // Exclusive prefix sum of n counts; *total = their sum.
  bool scan(const std::uint32_t* in, std::uint32_t* out, std::size_t n, std::uint32_t* total) {
    std::size_t bytes = 0;
    if (cub::DeviceScan::ExclusiveSum(nullptr, bytes, in, out, n) != cudaSuccess || !scan_temp.reserve(bytes))
      return false;
    if (cub::DeviceScan::ExclusiveSum(scan_temp.ptr, bytes, in, out, n) != cudaSuccess) return false;
    std::uint32_t last[2];
    if (cudaMemcpy(&last[0], out + n - 1, sizeof(std::uint32_t), cudaMemcpyDeviceToHost) != cudaSuccess ||
        cudaMemcpy(&last[1], in + n - 1, sizeof(std::uint32_t), cudaMemcpyDeviceToHost) != cudaSuccess)
      return false;
    *total = last[0] + last[1];
    return true;
  }
};

bool surfaceCudaAvailable(std::string* info) { return hapi_nodelet_kit::cudaDeviceUsable(info); }

CudaSurfaceVolume::CudaSurfaceVolume() : impl_(std::make_unique<Impl>()) {}
CudaSurfaceVolume::~CudaSurfaceVolume() = default;

SurfaceStatus CudaSurfaceVolume::upload(const TsdfVolume& volume) {
  Impl& m = *impl_;
  m.loaded = false;
  const std::size_t nv = volume.grid().size(), bytes = nv * sizeof(float);
  const bool ok = nv > 0 && m.tsdf.reserve(nv) && m.weight.reserve(nv) &&
                  cudaMemcpy(m.tsdf.ptr, volume.tsdf().data(), bytes, cudaMemcpyHostToDevice) == cudaSuccess &&
                  cudaMemcpy(m.weight.ptr, volume.weight().data(), bytes, cudaMemcpyHostToDevice) == cudaSuccess;
  if (!ok) {
    cudaGetLastError();
    return SurfaceStatus::kDeviceError;
  }
  m.grid = volume.grid();
  m.settings = volume.settings();
  m.loaded = true;
  return SurfaceStatus::kOk;
}

SurfaceStatus CudaSurfaceVolume::integrate(const DepthFrame& frame) {
  Impl& m = *impl_;
  if (!m.loaded) return SurfaceStatus::kNoVolume;
  const SurfaceStatus st = checkDepthFrame(frame, m.settings);
  if (st != SurfaceStatus::kOk) return st;
  const TsdfIntegrationParams p = integrationParams(m.grid, frame, m.settings);
  const std::size_t np = frame.depth.data.size(), bytes = np * sizeof(float);
  const bool has_weight = !frame.weight.empty();
  bool ok = m.depth.reserve(np) && (!has_weight || m.pixel_weight.reserve(np)) &&
            cudaEventRecord(m.start) == cudaSuccess &&
            cudaMemcpy(m.depth.ptr, frame.depth.data.data(), bytes, cudaMemcpyHostToDevice) == cudaSuccess &&
            (!has_weight ||
             cudaMemcpy(m.pixel_weight.ptr, frame.weight.data.data(), bytes, cudaMemcpyHostToDevice) == cudaSuccess);
  ok = ok && cudaEventRecord(m.kernel_start) == cudaSuccess &&
       launchIntegrate(p, m.depth.ptr, has_weight ? m.pixel_weight.ptr : nullptr, m.tsdf.ptr, m.weight.ptr);
  ok = ok && cudaEventRecord(m.end) == cudaSuccess && cudaEventSynchronize(m.end) == cudaSuccess;
  if (!ok) {
    cudaGetLastError();
    m.loaded = false;  // the kernel may have run part of the way
    return SurfaceStatus::kDeviceError;
  }
  cudaEventElapsedTime(&integrate_ms_, m.start, m.end);
  cudaEventElapsedTime(&integrate_kernel_ms_, m.kernel_start, m.end);
  return SurfaceStatus::kOk;
}

SurfaceStatus CudaSurfaceVolume::integrateHost(TsdfVolume* volume, const DepthFrame& frame) {
  // A bad frame is refused before the volume goes up.
  SurfaceStatus st = checkDepthFrame(frame, volume->settings());
  if (st != SurfaceStatus::kOk) return st;
  const auto t0 = std::chrono::steady_clock::now();
  st = upload(*volume);
  if (st == SurfaceStatus::kOk) st = integrate(frame);
  if (st == SurfaceStatus::kOk) st = download(volume);
  round_trip_ms_ = std::chrono::duration<float, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return st;
}

SurfaceStatus CudaSurfaceVolume::download(TsdfVolume* volume) const {
  const Impl& m = *impl_;
  if (!m.loaded) return SurfaceStatus::kNoVolume;
  if (volume->grid().dims != m.grid.dims) return SurfaceStatus::kSizeMismatch;
  const std::size_t nv = m.grid.size();
  std::vector<float> tsdf, weight;
  if (!hapi_surface::download(&tsdf, m.tsdf.ptr, nv) || !hapi_surface::download(&weight, m.weight.ptr, nv)) {
    cudaGetLastError();
    return SurfaceStatus::kDeviceError;
  }
  volume->mutableTsdf().swap(tsdf);
  volume->mutableWeight().swap(weight);
  return SurfaceStatus::kOk;
}

SurfaceStatus CudaSurfaceVolume::extractMesh(Mesh* mesh) {
  Impl& m = *impl_;
  if (!m.loaded) return SurfaceStatus::kNoVolume;
  const GridShape s = shapeOf(m.grid);
  const std::size_t nv = m.grid.size(), n_slots = nv * kEdgesPerPoint;
  const dim3 block(32, 8, 1);
  const dim3 cubes((s.nx + 31) / 32, (s.ny + 7) / 8, s.nz);
  std::uint32_t n_tri = 0, n_vtx = 0;
  bool ok = m.tri_count.reserve(nv) && m.tri_offset.reserve(nv) && m.edge_used.reserve(n_slots) &&
            m.vertex_id.reserve(n_slots) && cudaEventRecord(m.start) == cudaSuccess &&
            cudaMemset(m.edge_used.ptr, 0, n_slots * sizeof(std::uint32_t)) == cudaSuccess;
  if (ok) {
    countKernel<<<cubes, block>>>(s, m.tsdf.ptr, m.weight.ptr, static_cast<float>(m.settings.mesh_min_weight),
                                  m.tri_count.ptr, m.edge_used.ptr);
    ok = cudaGetLastError() == cudaSuccess;
  }
  ok = ok && m.scan(m.tri_count.ptr, m.tri_offset.ptr, nv, &n_tri) &&
       m.scan(m.edge_used.ptr, m.vertex_id.ptr, n_slots, &n_vtx);
  ok = ok && m.pos.reserve(3 * std::size_t{n_vtx} + 3) && m.normal.reserve(3 * std::size_t{n_vtx} + 3) &&
       m.t.reserve(std::size_t{n_vtx} + 1) && m.edge_ends.reserve(2 * std::size_t{n_vtx} + 2) &&
       m.faces.reserve(3 * std::size_t{n_tri} + 3);
  if (ok && n_tri > 0) {
    const std::size_t blocks = (n_slots + 255) / 256;
    vertexKernel<<<static_cast<unsigned int>(blocks), 256>>>(s, n_slots, m.tsdf.ptr, m.weight.ptr, m.edge_used.ptr,
                                                             m.vertex_id.ptr, m.pos.ptr, m.normal.ptr, m.t.ptr,
                                                             m.edge_ends.ptr);
    faceKernel<<<cubes, block>>>(s, m.tsdf.ptr, m.tri_count.ptr, m.tri_offset.ptr, m.vertex_id.ptr, m.pos.ptr,
                                 m.normal.ptr, m.faces.ptr);
    ok = cudaGetLastError() == cudaSuccess;
  }
  // Into *mesh itself (its memory reused); a failure leaves it cleared.
  mesh->values.clear();
  mesh->value_weights.clear();
  ok = ok && cudaEventRecord(m.kernels_end) == cudaSuccess && m.downloadMesh(n_vtx, n_tri, mesh);
  ok = ok && cudaEventRecord(m.end) == cudaSuccess && cudaEventSynchronize(m.end) == cudaSuccess;
  if (!ok) {
    cudaGetLastError();
    *mesh = Mesh();
    return SurfaceStatus::kDeviceError;
  }
  cudaEventElapsedTime(&mesh_ms_, m.start, m.end);
  cudaEventElapsedTime(&mesh_kernels_ms_, m.start, m.kernels_end);
  return SurfaceStatus::kOk;
}

}  // namespace hapi_surface
