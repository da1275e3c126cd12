// Host copy of a landmark pool's descriptors, in slot order, and the
// brute-force Hamming best/second-best search over it. Used by every back end
// whose descriptors do not live on a device (the ES-EKF's cpu storage, the
// SEIF, the graph and particle back ends), so all of them match alike.
#pragma once

#include "hapi_eskf/backend/association_source.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hapi_eskf {

// Best and second-best of each query (n_query * length bytes) among the K
// pool descriptors (K * length bytes). `out` must hold n_query matches
// initialised empty; ties keep the lower slot as best.
void matchHamming(const uint8_t* queries, int n_query, const uint8_t* pool, int K, int length,
                  std::vector<DescriptorMatch>* out);

class DescriptorPool {
 public:
  explicit DescriptorPool(int length = 0) : length_(length) {}

  int length() const { return length_; }
  int size() const { return length_ > 0 ? static_cast<int>(bytes_.size() / length_) : size_; }
  void clear() { bytes_.clear(); size_ = 0; }
  // Appends one descriptor (length() bytes; ignored when length() is 0).
  void append(const uint8_t* descriptor);
  // Removes the given slots with the pool's removal plan (removal_plan.hpp).
  void remove(const std::vector<int>& slots);
  // matchDescriptors() of AssociationSource over this pool (same checks).
  Status match(const uint8_t* queries, int n_query, std::vector<DescriptorMatch>* out) const;
  const std::vector<uint8_t>& bytes() const { return bytes_; }
  std::size_t memoryBytes() const { return bytes_.capacity(); }

 private:
  int length_;
  int size_ = 0;  // count when length_ is 0
  std::vector<uint8_t> bytes_;
};

}  // namespace hapi_eskf
