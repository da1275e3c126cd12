// Which landmark ends up in which slot after a removal (docs/DESIGN.md "Removal":
// fixed slots, no shifting). The backends, the filter's host mirror and the
// benchmark all apply this one plan, so their slot orders never diverge.
//
// Rule ("fill holes from the tail"): with K landmarks and r removed, the new
// pool is slots 0..K-r-1. A kept landmark below K-r stays where it is; the
// kept landmarks at slots >= K-r (as many as there are removed slots below
// K-r) move, in increasing slot order, into those removed slots, also in
// increasing order. Cost O(n) per moved landmark instead of moving the whole
// lower triangle behind the first removed slot (the compaction it replaces
// moved ~2 x 37 GB per iteration at K = 32000).
#pragma once

#include <vector>

namespace hapi_eskf {

struct SlotMove {
  int from = -1;  // old slot (>= K - r), kept
  int to = -1;    // new slot (< K - r), one of the removed ones
};

// The moves for removing `removed` (distinct, each in [0, K); any order) from
// a pool of K. Empty when no kept landmark sits at or above K - r.
std::vector<SlotMove> tailFillMoves(int K, const std::vector<int>& removed);

// The same plan as a map: old slot of every new slot (length K - r).
std::vector<int> oldSlotOfNew(int K, const std::vector<int>& removed);
// ... from moves already computed for a pool that shrinks to K_new.
std::vector<int> oldSlotOfNew(int K_new, const std::vector<SlotMove>& moves);

// Applies the plan to a per-slot host array (size K -> K - r).
template <typename V>
void applyRemoval(const std::vector<SlotMove>& moves, int K_new, std::vector<V>* values) {
  for (const SlotMove& m : moves) (*values)[m.to] = std::move((*values)[m.from]);
  values->resize(K_new);
}

}  // namespace hapi_eskf
