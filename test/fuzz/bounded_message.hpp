// Deserialisation of fuzzer bytes into ROS messages, as roscpp does for a
// message it received, with one difference: every allocation the
// deserialiser makes is bounded by the size of the input. A serialised array
// starts with its element count, and roscpp's deserialiser resizes the vector
// to that count before it reads (and range-checks) the elements, so a 20-byte
// message that claims 4e9 elements asks for gigabytes. In a running node
// that is roscpp's own behaviour (its deserialiser catches the bad_alloc and
// drops the message; docs/RELIABILITY.md "Coverage-guided fuzzing"); here it
// would only report the fuzzer's memory limit on third-party code and hide
// every finding behind it. Messages are first read into the
// bounded-allocator instance of the message template, then re-serialised
// (now consistent and no larger than the input) into the std::allocator
// instance that our code takes.
#pragma once

#include <ros/serialization.h>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <new>
#include <vector>

namespace hapi_fuzz {

// The largest single allocation a deserialisation may make [bytes].
inline std::size_t& allocationLimit() {
  static std::size_t limit = 0;
  return limit;
}

template <typename T>
struct BoundedAllocator {
  using value_type = T;
  template <typename U>
  struct rebind {
    using other = BoundedAllocator<U>;
  };
  BoundedAllocator() = default;
  template <typename U>
  BoundedAllocator(const BoundedAllocator<U>&) {}
  T* allocate(std::size_t n) {
    if (n > allocationLimit() / sizeof(T)) throw std::bad_alloc();
    return std::allocator<T>().allocate(n);
  }
  void deallocate(T* p, std::size_t n) { std::allocator<T>().deallocate(p, n); }
  template <typename U>
  bool operator==(const BoundedAllocator<U>&) const { return true; }
  template <typename U>
  bool operator!=(const BoundedAllocator<U>&) const { return false; }
};

// Bytes -> message. False when roscpp's deserialiser rejects the bytes
// (stream overrun, or a count the input cannot hold).
template <template <class> class Message>
bool deserialise(const std::uint8_t* data, std::size_t size, Message<std::allocator<void>>* out) {
  namespace ser = ros::serialization;
  allocationLimit() = 4 * size + 4096;  // in-memory elements may be larger than on the wire
  Message<BoundedAllocator<void>> bounded;
  try {
    ser::IStream in(const_cast<std::uint8_t*>(data), static_cast<std::uint32_t>(size));
    ser::deserialize(in, bounded);
  } catch (const ros::serialization::StreamOverrunException&) {
    return false;
  } catch (const std::bad_alloc&) {
    return false;
  }
  std::vector<std::uint8_t> buffer(ser::serializationLength(bounded));
  ser::OStream o(buffer.data(), static_cast<std::uint32_t>(buffer.size()));
  ser::serialize(o, bounded);
  ser::IStream in(buffer.data(), static_cast<std::uint32_t>(buffer.size()));
  ser::deserialize(in, *out);
  return true;
}

// The fuzzer input as a sequence of records, each a little-endian uint32
// length followed by that many bytes (one serialised message each); a
// truncated last record ends the sequence.
class Records {
 public:
  Records(const std::uint8_t* data, std::size_t size) : p_(data), end_(data + size) {}
  bool next(const std::uint8_t** data, std::size_t* size) {
    if (end_ - p_ < 4) return false;
    std::uint32_t n = 0;
    for (int i = 3; i >= 0; --i) n = (n << 8) | p_[i];
    p_ += 4;
    if (static_cast<std::size_t>(end_ - p_) < n) return false;
    *data = p_;
    *size = n;
    p_ += n;
    return true;
  }

 private:
  const std::uint8_t* p_;
  const std::uint8_t* end_;
};

// One record as written by the seed generator (the inverse of Records).
template <typename M>
void appendRecord(const M& msg, std::vector<std::uint8_t>* out) {
  namespace ser = ros::serialization;
  const std::uint32_t n = ser::serializationLength(msg);
  for (int i = 0; i < 4; ++i) out->push_back(static_cast<std::uint8_t>(n >> (8 * i)));
  const std::size_t at = out->size();
  out->resize(at + n);
  ser::OStream o(out->data() + at, n);
  ser::serialize(o, msg);
}

}  // namespace hapi_fuzz
