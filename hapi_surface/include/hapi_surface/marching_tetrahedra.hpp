// The mesh rules of marching tetrahedra (docs/DESIGN.md "Surface", mesh),
// written once for extractMesh() on the CPU and the CUDA mesher: the Kuhn
// split of a cube, the triangles of one tetrahedron, a vertex on a grid
// edge with its normal, the TSDF gradient and a triangle's winding. Single
// precision, no fused multiply-add either side (tsdf_math.hpp), so both give
// the same bits.
#pragma once

#include "hapi_surface/tsdf_math.hpp"

namespace hapi_surface {

// Corner c (0..3) of tetrahedron t (0..5) of the Kuhn split of a cube
// (corners as cubeOffsets()): 6 tetrahedra sharing the diagonal 0-6. The
// same split in every cube cuts each shared face along the same diagonal
// from both sides, so neighbouring tetrahedra meet exactly. Every edge of
// these tetrahedra joins two corners whose coordinates differ by 0 or +1
// along each axis (a Kuhn simplex is a monotone chain), so an edge is one of
// 7 directions from its lower grid point (edgeDirection()).
HAPI_SURFACE_HD int kuhnCorner(int t, int c) {
  const int tet[6][4] = {{0, 5, 1, 6}, {0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}};
  return tet[t][c];
}

// The grid offset (x, y, z in {0, 1}) of cube corner c (cubeOffsets()'s order).
HAPI_SURFACE_HD void cornerOffset(int c, int* dx, int* dy, int* dz) {
  const int x[8] = {0, 1, 1, 0, 0, 1, 1, 0}, y[8] = {0, 0, 1, 1, 0, 0, 1, 1}, z[8] = {0, 0, 0, 0, 1, 1, 1, 1};
  *dx = x[c];
  *dy = y[c];
  *dz = z[c];
}

// The edge between cube corners a and b as (its lower corner, direction
// 0..6 = dx + 2 dy + 4 dz - 1 of the upper corner's offset from it).
HAPI_SURFACE_HD int edgeDirection(int a, int b, int* lower) {
  int ax, ay, az, bx, by, bz;
  cornerOffset(a, &ax, &ay, &az);
  cornerOffset(b, &bx, &by, &bz);
  const bool a_low = ax <= bx && ay <= by && az <= bz;
  *lower = a_low ? a : b;
  const int s = a_low ? 1 : -1;
  return s * ((bx - ax) + 2 * (by - ay) + 4 * (bz - az)) - 1;
}

// A tetrahedron's triangles as corner pairs: up to 2 triangles of 3 edges,
// each edge (inside corner or lone corner first, as the cases below write
// it). Returns the number of triangles. f: the TSDF at the cube's 8 corners;
// a corner is inside where f < 0.
struct TetTriangles {
  int edge[2][3][2];
};

HAPI_SURFACE_HD int tetrahedronTriangles(int t, const float* f, TetTriangles* out) {
  int in[4], outside[4], n_in = 0, n_out = 0;
  for (int c = 0; c < 4; ++c) {
    const int k = kuhnCorner(t, c);
    if (f[k] < 0.f) in[n_in++] = k;
    else outside[n_out++] = k;
  }
  if (n_in == 0 || n_out == 0) return 0;
  if (n_in == 1 || n_out == 1) {
    const int lone = n_in == 1 ? in[0] : outside[0];
    const int* others = n_in == 1 ? outside : in;
    for (int e = 0; e < 3; ++e) {
      out->edge[0][e][0] = lone;
      out->edge[0][e][1] = others[e];
    }
    return 1;
  }
  // Two in, two out: a quad whose corners go round the tetrahedron,
  // a = (in0, out0), b = (in0, out1), c = (in1, out1), d = (in1, out0),
  // as the triangles (a, b, c) and (a, c, d).
  const int quad[4][2] = {{in[0], outside[0]}, {in[0], outside[1]}, {in[1], outside[1]}, {in[1], outside[0]}};
  const int order[2][3] = {{0, 1, 2}, {0, 2, 3}};
  for (int tri = 0; tri < 2; ++tri)
    for (int e = 0; e < 3; ++e) {
      out->edge[tri][e][0] = quad[order[tri][e]][0];
      out->edge[tri][e][1] = quad[order[tri][e]][1];
    }
  return 2;
}

// The position [m] of grid point (i, j, k): the centre of that voxel,
// origin + voxel (c + 1/2), in double, then single precision.
HAPI_SURFACE_HD void gridPointPosition(const double* origin, double voxel, int i, int j, int k, float* pos) {
  const int c[3] = {i, j, k};
  for (int a = 0; a < 3; ++a) pos[a] = static_cast<float>(origin[a] + voxel * (static_cast<double>(c[a]) + 0.5));
}

// The TSDF gradient at grid point (i, j, k) of an nx x ny x nz grid:
// central differences, one-sided at the border and next to an unobserved
// voxel (weight <= 0), zero where neither side is usable [per voxel].
HAPI_SURFACE_HD void tsdfGradient(const float* tsdf, const float* weight, int nx, int ny, int nz, int i, int j, int k,
                                  float* grad) {
  const int c[3] = {i, j, k}, dims[3] = {nx, ny, nz};
  const unsigned int g = (static_cast<unsigned int>(k) * ny + j) * static_cast<unsigned int>(nx) + i;
  const unsigned int stride[3] = {1u, static_cast<unsigned int>(nx), static_cast<unsigned int>(nx) * ny};
  for (int a = 0; a < 3; ++a) {
    int lo = c[a], hi = c[a];
    unsigned int il = g, ih = g;
    if (c[a] > 0) lo -= 1, il -= stride[a];
    if (c[a] + 1 < dims[a]) hi += 1, ih += stride[a];
    if (weight[il] <= 0.f) lo = c[a], il = g;
    if (weight[ih] <= 0.f) hi = c[a], ih = g;
    const int span = hi - lo;
    grad[a] = span > 0 ? (tsdf[ih] - tsdf[il]) / static_cast<float>(span) : 0.f;
  }
}

// The vertex where the TSDF crosses zero on the edge from grid point a (at
// pa, value fa, gradient na) to b: its position, unit normal (the gradient
// interpolated along the edge, normalised; +z where it vanishes) and the
// fraction t from a.
HAPI_SURFACE_HD void edgeVertex(const float* pa, const float* pb, float fa, float fb, const float* na,
                                const float* nb, float* pos, float* normal, float* t_out) {
  const float t = fa / (fa - fb);
  float n[3];
  for (int a = 0; a < 3; ++a) {
    pos[a] = pa[a] + t * (pb[a] - pa[a]);
    n[a] = (1.f - t) * na[a] + t * nb[a];
  }
  const float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int a = 0; a < 3; ++a) normal[a] = len > 0.f ? n[a] / len : (a == 2 ? 1.f : 0.f);
  *t_out = t;
}

// Whether the triangle (a, b, c) is counter-clockwise seen from the side its
// vertex normals point to; if not, b and c are swapped.
HAPI_SURFACE_HD bool windingAgreesWithNormals(const float* va, const float* vb, const float* vc, const float* na,
                                              const float* nb, const float* nc) {
  const float e1[3] = {vb[0] - va[0], vb[1] - va[1], vb[2] - va[2]};
  const float e2[3] = {vc[0] - va[0], vc[1] - va[1], vc[2] - va[2]};
  const float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
  const float out[3] = {na[0] + nb[0] + nc[0], na[1] + nb[1] + nc[1], na[2] + nb[2] + nc[2]};
  return !(n[0] * out[0] + n[1] * out[1] + n[2] * out[2] < 0.f);
}

}  // namespace hapi_surface
