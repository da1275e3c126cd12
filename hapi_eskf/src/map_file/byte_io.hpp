// Little-endian encoding of the map file's fields (map_format.hpp): an
// appending writer and a bounds-checked reader that never reads past its end.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace hapi_eskf {
namespace map_file {

class ByteWriter {
 public:
  void u8(uint8_t v) { bytes_.push_back(v); }
  void u32(uint32_t v) { put(v, 4); }
  void u64(uint64_t v) { put(v, 8); }
  void f64(double v) {
    uint64_t bits;
    std::memcpy(&bits, &v, 8);
    put(bits, 8);
  }
  void raw(const void* data, std::size_t n) {
    const auto* p = static_cast<const uint8_t*>(data);
    bytes_.insert(bytes_.end(), p, p + n);
  }
  void name(const std::string& s) {
    u32(static_cast<uint32_t>(s.size()));
    raw(s.data(), s.size());
  }
  std::size_t size() const { return bytes_.size(); }
  std::vector<uint8_t>& bytes() { return bytes_; }
  // Overwrites 8 bytes at `at` (a table entry's offset or size).
  void patchU64(std::size_t at, uint64_t v) {
    for (int i = 0; i < 8; ++i) bytes_[at + i] = static_cast<uint8_t>(v >> (8 * i));
  }

 private:
  void put(uint64_t v, int n) {
    for (int i = 0; i < n; ++i) bytes_.push_back(static_cast<uint8_t>(v >> (8 * i)));
  }
  std::vector<uint8_t> bytes_;
};

// Every getter returns false (and reads nothing) when fewer bytes are left.
class ByteReader {
 public:
  ByteReader(const uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::size_t left() const { return size_ - pos_; }
  bool u8(uint8_t* v) {
    if (left() < 1) return false;
    *v = data_[pos_++];
    return true;
  }
  bool u32(uint32_t* v) {
    uint64_t w;
    if (!get(&w, 4)) return false;
    *v = static_cast<uint32_t>(w);
    return true;
  }
  bool u64(uint64_t* v) { return get(v, 8); }
  bool f64(double* v) {
    uint64_t bits;
    if (!get(&bits, 8)) return false;
    std::memcpy(v, &bits, 8);
    return true;
  }
  bool raw(uint8_t* out, std::size_t n) {
    if (left() < n) return false;
    std::memcpy(out, data_ + pos_, n);
    pos_ += n;
    return true;
  }
  // A length-prefixed name of at most max_bytes; false when truncated or longer.
  bool name(std::string* s, uint32_t max_bytes) {
    uint32_t n;
    if (!u32(&n) || n > max_bytes || left() < n) return false;
    s->assign(reinterpret_cast<const char*>(data_ + pos_), n);
    pos_ += n;
    return true;
  }

 private:
  bool get(uint64_t* v, int n) {
    if (left() < static_cast<std::size_t>(n)) return false;
    uint64_t w = 0;
    for (int i = 0; i < n; ++i) w |= static_cast<uint64_t>(data_[pos_ + i]) << (8 * i);
    pos_ += n;
    *v = w;
    return true;
  }
  const uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

}  // namespace map_file
}  // namespace hapi_eskf
