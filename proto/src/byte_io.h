#pragma once
/// Little-endian writer and bounds-checked reader for the game channel's hand-written packets.
/// The reader never reads past its span: a short read sets failed() and yields zeros.

#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

namespace ricochet::proto {

class ByteWriter {
 public:
  explicit ByteWriter(std::vector<std::uint8_t>& out) : out_(out) {}
  void u8(std::uint8_t value) { out_.push_back(value); }
  void u16(std::uint16_t value) { unsigned_le(value, 2); }
  void u32(std::uint32_t value) { unsigned_le(value, 4); }
  void u64(std::uint64_t value) { unsigned_le(value, 8); }
  void bytes(std::span<const std::uint8_t> data) {
    out_.insert(out_.end(), data.begin(), data.end());
  }

 private:
  void unsigned_le(std::uint64_t value, int count) {
    for (int i = 0; i < count; ++i) out_.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
  }
  std::vector<std::uint8_t>& out_;
};

class ByteReader {
 public:
  explicit ByteReader(std::span<const std::uint8_t> data) : data_(data) {}
  std::uint8_t u8() { return static_cast<std::uint8_t>(unsigned_le(1)); }
  std::uint16_t u16() { return static_cast<std::uint16_t>(unsigned_le(2)); }
  std::uint32_t u32() { return static_cast<std::uint32_t>(unsigned_le(4)); }
  std::uint64_t u64() { return unsigned_le(8); }
  /// The next `count` bytes, or an empty span (and failed()) when fewer remain.
  std::span<const std::uint8_t> bytes(std::size_t count) {
    if (count > remaining()) {
      failed_ = true;
      position_ = data_.size();
      return {};
    }
    auto out = data_.subspan(position_, count);
    position_ += count;
    return out;
  }
  template <std::size_t N>
  void copy_to(std::array<std::uint8_t, N>& out) {
    auto in = bytes(N);
    if (!in.empty()) std::memcpy(out.data(), in.data(), N);
  }
  std::span<const std::uint8_t> rest() { return bytes(remaining()); }
  std::size_t remaining() const { return data_.size() - position_; }
  bool failed() const { return failed_; }

 private:
  std::uint64_t unsigned_le(int count) {
    auto in = bytes(static_cast<std::size_t>(count));
    std::uint64_t value = 0;
    for (std::size_t i = 0; i < in.size(); ++i) value |= std::uint64_t{in[i]} << (8 * i);
    return value;
  }
  std::span<const std::uint8_t> data_;
  std::size_t position_ = 0;
  bool failed_ = false;
};

}  // namespace ricochet::proto
