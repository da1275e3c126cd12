#include "hapi_eskf/keyframes/keyframe_index.hpp"

#include <algorithm>
#include <cmath>

namespace hapi_eskf {
namespace {

std::uint16_t wordAt(const std::uint8_t* d, int position) {
  return static_cast<std::uint16_t>(d[2 * position] | (d[2 * position + 1] << 8));
}

}  // namespace

void KeyframeIndex::add(std::size_t index, const Keyframe& kf) {
  const int words = kf.descriptor_length / 2;
  const auto id = static_cast<std::uint32_t>(index);
  for (std::size_t i = 0; i < kf.size(); ++i) {
    const std::uint8_t* d = kf.descriptor(i);
    for (int p = 0; p < words; ++p) {
      std::vector<std::uint32_t>& list = lists_[key(p, wordAt(d, p))];
      // Keyframes are added in order: one entry per keyframe and word.
      if (list.empty() || list.back() != id) list.push_back(id);
    }
  }
  keyframes_ = std::max(keyframes_, index + 1);
}

void KeyframeIndex::clear() {
  lists_.clear();
  keyframes_ = 0;
}

std::vector<KeyframeVotes> KeyframeIndex::candidates(const std::uint8_t* descriptors, std::size_t n, int length,
                                                     std::size_t top, int min_votes) const {
  std::vector<int> votes(keyframes_, 0);
  const int words = length / 2;
  // A word most keyframes hold tells them apart no better than chance.
  const std::size_t longest = std::max<std::size_t>(8, static_cast<std::size_t>(std::ceil(kMaxListShare * keyframes_)));
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* d = descriptors + i * static_cast<std::size_t>(length);
    for (int p = 0; p < words; ++p) {
      const auto it = lists_.find(key(p, wordAt(d, p)));
      if (it == lists_.end() || it->second.size() > longest) continue;
      for (std::uint32_t k : it->second) ++votes[k];
    }
  }
  std::vector<KeyframeVotes> out;
  for (std::size_t k = 0; k < votes.size(); ++k)
    if (votes[k] >= min_votes) out.push_back({k, votes[k]});
  const std::size_t keep = std::min(top, out.size());
  std::partial_sort(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(keep), out.end(),
                    [](const KeyframeVotes& a, const KeyframeVotes& b) {
                      return a.votes > b.votes || (a.votes == b.votes && a.keyframe < b.keyframe);
                    });
  out.resize(keep);
  return out;
}

}  // namespace hapi_eskf
