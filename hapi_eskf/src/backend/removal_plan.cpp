// "Fill holes from the tail" removal plan (include/hapi_eskf/backend/removal_plan.hpp).
#include "hapi_eskf/backend/removal_plan.hpp"

namespace hapi_eskf {

std::vector<SlotMove> tailFillMoves(int K, const std::vector<int>& removed) {
  std::vector<char> gone(static_cast<std::size_t>(K > 0 ? K : 0), 0);
  for (int s : removed) gone[s] = 1;
  const int K_new = K - static_cast<int>(removed.size());
  std::vector<SlotMove> moves;
  int hole = 0;
  for (int from = K_new; from < K; ++from) {
    if (gone[from]) continue;
    while (!gone[hole]) ++hole;  // a kept slot above K_new guarantees a hole below it
    moves.push_back({from, hole++});
  }
  return moves;
}

std::vector<int> oldSlotOfNew(int K_new, const std::vector<SlotMove>& moves) {
  std::vector<int> old(static_cast<std::size_t>(K_new));
  for (int k = 0; k < K_new; ++k) old[k] = k;
  for (const SlotMove& m : moves) old[m.to] = m.from;
  return old;
}

std::vector<int> oldSlotOfNew(int K, const std::vector<int>& removed) {
  return oldSlotOfNew(K - static_cast<int>(removed.size()), tailFillMoves(K, removed));
}

}  // namespace hapi_eskf
