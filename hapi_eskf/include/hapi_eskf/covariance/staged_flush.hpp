// The staged flush of the partitioned update (docs/DESIGN.md "Staged
// flush"), the bookkeeping one copy for its CPU and CUDA variants: which
// entries of the stored lower triangle still owe the correction of a flushed
// epoch, how far each share advances, and which entries a removal's slot
// moves settle.
//
// A staged flush writes the active rows at once and leaves the passive block's
// correction  C_BB -= Xp Psip Xp^T  pending (Xp: the flushed epoch's X with
// its active rows and every later row zero). The rows of the lower triangle
// are corrected in order, a share per update: rows [0, done) are. Entry
// (i, k) of the stored C therefore still owes  Xp_i Psip Xp_k^T  exactly when
// max(i, k) >= done.
#pragma once

#include "hapi_eskf/backend/removal_plan.hpp"
#include "hapi_eskf/types.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace hapi_eskf {
namespace partition {

inline bool owesPending(int i, int k, int done) { return std::max(i, k) >= done; }

// The diagonal block at state row r of C^0: the stored block minus the
// entries' pending share `owed` (Xp_r Psip Xp_r^T) where they still owe it.
inline Mat3 withoutOwed(const Mat3& stored, const Mat3& owed, int r, int done) {
  Mat3 B = stored;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k)
      if (owesPending(r + i, r + k, done)) B(i, k) -= owed(i, k);
  return B;
}

// End of the next share of the rows [done, n) when `shares_left` shares
// remain: row panel work grows with the row (row i has i + 1 entries), so
// the shares end where the remaining entries divide evenly.
inline int nextStagedRow(int done, int n, int shares_left) {
  if (shares_left <= 1 || done >= n) return n;
  const double d = done, nn = n;
  const int next = static_cast<int>(std::ceil(std::sqrt(d * d + (nn * nn - d * d) / shares_left)));
  return std::min(n, std::max(next, done + 1));
}

// A removal moves landmarks from the tail into holes (`moves`, slots). An
// entry that moves keeps its debt, but its status is read from its new place:
// an entry whose old column row was at or past `done` and whose new place is
// before it (both indices < done) would pass for corrected. The state rows
// returned (new rows, ascending) are those of moved landmarks that crossed
// `done`; every entry (i, k) with k one of them and i < done owes its share
// now (pairs of two such rows once).
inline std::vector<int> rowsSettledByMoves(const std::vector<SlotMove>& moves, int done, int pose_dim) {
  std::vector<int> rows;
  for (const SlotMove& mv : moves)
    for (int r = 0; r < 3; ++r) {
      const int from = landmarkRow(mv.from, pose_dim) + r, to = landmarkRow(mv.to, pose_dim) + r;
      if (from >= done && to < done) rows.push_back(to);
    }
  std::sort(rows.begin(), rows.end());
  return rows;
}

}  // namespace partition
}  // namespace hapi_eskf
