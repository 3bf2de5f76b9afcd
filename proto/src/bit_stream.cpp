#include "ricochet/proto/bit_stream.h"

#include <bit>

namespace ricochet::proto {

const std::vector<std::uint8_t>& BitWriter::bytes() const {
  bytes_.resize(flushed_bytes_);
  for (int left = 64 - free_bits_; left > 0; left -= 8) {
    const std::uint64_t top = left >= 8 ? pending_ >> (left - 8) : pending_ << (8 - left);
    bytes_.push_back(static_cast<std::uint8_t>(top));
  }
  return bytes_;
}

void BitWriter::clear() {
  flushed_bytes_ = 0;  // bytes_ keeps its size as room for the next stream
  pending_ = 0;
  free_bits_ = 64;
  bit_count_ = 0;
}

bool BitReader::only_padding_left() const {
  if (failed_) return false;
  const std::size_t left = bytes_.size() * 8 - position_;
  if (left >= 8) return false;
  if (left == 0) return true;
  const std::uint8_t mask = static_cast<std::uint8_t>((1u << left) - 1);
  return (bytes_.back() & mask) == 0;
}

}  // namespace ricochet::proto
