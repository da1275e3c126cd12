// Reads and moves on a symmetric matrix stored by its LOWER triangle (the CPU
// backends' C, covariance_backend.hpp storage contract), written once for the
// dense and the partitioned CPU backend.
#pragma once

#include "hapi_eskf/backend/removal_plan.hpp"
#include "hapi_eskf/types.hpp"

#include <Eigen/Core>

#include <vector>

namespace hapi_eskf {
namespace lower_triangle {

// Full columns c0..c0+w-1 (rows 0..n-1) of the symmetric matrix into the
// first n rows of G: entries above the diagonal come from row c (strided),
// those on and below from column c (contiguous). O(n w).
template <typename Dst>
void gatherColumns(const Eigen::MatrixXd& C, int c0, int w, int n, Dst&& G) {
  for (int t = 0; t < w; ++t) {
    const int c = c0 + t;
    auto g = G.col(t);
    g.head(c) = C.row(c).head(c).transpose();
    g.segment(c, n - c) = C.col(c).segment(c, n - c);
  }
}

// The symmetrised d x d diagonal block at (r, r).
inline Eigen::MatrixXd symmetricBlock(const Eigen::MatrixXd& C, int r, int d) {
  Eigen::MatrixXd B = C.block(r, r, d, d).triangularView<Eigen::Lower>();
  B.triangularView<Eigen::StrictlyUpper>() = B.transpose().triangularView<Eigen::StrictlyUpper>();
  return B;
}

// Removal by the shared plan ("fill holes from the tail", removal_plan.hpp):
// each moved landmark's 3 rows/columns (lower-triangle entries against every
// index of the new state) are copied into its new slot. Every source index is
// >= the new state dimension and every destination < it, so the copies never
// overwrite a source. Returns the moves (the caller moves its own per-slot data).
inline std::vector<SlotMove> fillHolesFromTail(Eigen::MatrixXd* C, int K, const std::vector<int>& slots, int P) {
  const int K_new = K - static_cast<int>(slots.size());
  const int n_new = stateDim(K_new, P);
  const std::vector<SlotMove> moves = tailFillMoves(K, slots);
  const std::vector<int> old_slot = oldSlotOfNew(K_new, moves);
  auto oldIndex = [&](int j) { return j < P ? j : landmarkRow(old_slot[(j - P) / 3], P) + (j - P) % 3; };
  auto at = [&](int i, int j) -> double& { return i >= j ? (*C)(i, j) : (*C)(j, i); };
  for (const SlotMove& mv : moves)
    for (int r = 0; r < 3; ++r) {
      const int dst = landmarkRow(mv.to, P) + r, src = landmarkRow(mv.from, P) + r;
      for (int j = 0; j < n_new; ++j) at(dst, j) = at(src, oldIndex(j));
    }
  return moves;
}

}  // namespace lower_triangle
}  // namespace hapi_eskf
