// Host descriptors and Hamming matching (descriptor_pool.hpp).
#include "hapi_eskf/backend/descriptor_pool.hpp"

#include "hapi_eskf/backend/removal_plan.hpp"

#include <cstring>

namespace hapi_eskf {
namespace {

int popcount64(uint64_t x) { return __builtin_popcountll(x); }

}  // namespace

void matchHamming(const uint8_t* queries, int n_query, const uint8_t* pool, int K, int length,
                  std::vector<DescriptorMatch>* out) {
  const int words = length / 8, tail = length % 8;
  for (int q = 0; q < n_query; ++q) {
    const uint8_t* a = queries + static_cast<std::size_t>(q) * length;
    DescriptorMatch& M = (*out)[q];
    for (int k = 0; k < K; ++k) {
      const uint8_t* b = pool + static_cast<std::size_t>(k) * length;
      int d = 0;
      for (int w = 0; w < words; ++w) {
        uint64_t x, y;
        std::memcpy(&x, a + 8 * w, 8);
        std::memcpy(&y, b + 8 * w, 8);
        d += popcount64(x ^ y);
      }
      for (int t = 0; t < tail; ++t) d += popcount64(static_cast<uint64_t>(a[8 * words + t] ^ b[8 * words + t]));
      if (d < M.best_distance) {
        M.second_distance = M.best_distance;
        M.second_slot = M.best_slot;
        M.best_distance = d;
        M.best_slot = k;
      } else if (d < M.second_distance) {
        M.second_distance = d;
        M.second_slot = k;
      }
    }
  }
}

void DescriptorPool::append(const uint8_t* descriptor) {
  if (length_ == 0) {
    ++size_;
    return;
  }
  const std::size_t at = bytes_.size();
  bytes_.resize(at + length_, 0);
  if (descriptor) std::memcpy(&bytes_[at], descriptor, length_);
}

void DescriptorPool::remove(const std::vector<int>& slots) {
  const int K = size(), K_new = K - static_cast<int>(slots.size());
  if (length_ == 0) {
    size_ = K_new;
    return;
  }
  for (const SlotMove& mv : tailFillMoves(K, slots))
    std::memcpy(&bytes_[static_cast<std::size_t>(mv.to) * length_], &bytes_[static_cast<std::size_t>(mv.from) * length_],
                length_);
  bytes_.resize(static_cast<std::size_t>(K_new) * length_);
}

Status DescriptorPool::match(const uint8_t* queries, int n_query, std::vector<DescriptorMatch>* out) const {
  if (!out || n_query < 0 || (n_query > 0 && !queries)) return Status::kInvalidArgument;
  out->assign(n_query, DescriptorMatch());
  if (n_query == 0 || size() == 0 || length_ == 0) return Status::kOk;
  matchHamming(queries, n_query, bytes_.data(), size(), length_, out);
  return Status::kOk;
}

}  // namespace hapi_eskf
