// Which stored keyframes share descriptors with a query frame, without
// comparing it with each (docs/DESIGN.md "Keyframes"). A binary descriptor
// is cut into 16-bit words; the index maps (word position, word value) to the
// keyframes holding a descriptor with that word. Two views of one point
// differ in a few bits, so many of their words are equal; two unrelated
// descriptors share a given word with probability 2^-16. A query's
// descriptors vote for every keyframe in their words' lists, and the
// keyframes with the most votes are the candidates. Words that more than
// kMaxListShare of the keyframes hold (a flat patch's all-zero words) say
// nothing and are not counted.
#pragma once

#include "hapi_eskf/keyframes/keyframe.hpp"

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace hapi_eskf {

struct KeyframeVotes {
  std::size_t keyframe = 0;  // index into the store's keyframes
  int votes = 0;
};

class KeyframeIndex {
 public:
  static constexpr double kMaxListShare = 0.25;

  // Adds keyframe number `index` (the store's order) with its descriptors.
  void add(std::size_t index, const Keyframe& kf);
  void clear();
  // The `top` keyframes with the most votes from `n` descriptors of
  // `length` bytes (at least min_votes each), most votes first.
  std::vector<KeyframeVotes> candidates(const std::uint8_t* descriptors, std::size_t n, int length, std::size_t top,
                                        int min_votes) const;
  std::size_t keyframes() const { return keyframes_; }

 private:
  static std::uint32_t key(int position, std::uint16_t word) {
    return (static_cast<std::uint32_t>(position) << 16) | word;
  }
  std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> lists_;
  std::size_t keyframes_ = 0;
};

}  // namespace hapi_eskf
