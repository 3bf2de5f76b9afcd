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

std::uint64_t BitReader::read_bits(int bits) {
  if (failed_ || static_cast<std::size_t>(bits) > bytes_.size() * 8 - position_) {
    failed_ = true;
    return 0;
  }
  std::uint64_t value = 0;
  for (int i = 0; i < bits; ++i) {
    const std::uint8_t byte = bytes_[position_ / 8];
    value = (value << 1) | ((byte >> (7 - position_ % 8)) & 1u);
    ++position_;
  }
  return value;
}

std::uint64_t BitReader::read_exp_golomb(int order) {
  int zeros = 0;
  while (!failed_ && read_bits(1) == 0) {
    if (++zeros + order + 1 > kMaxExpGolombWidth) failed_ = malformed_ = true;
  }
  if (failed_) return 0;
  // The leading 1 was read; the remaining zeros + order bits follow.
  const int rest = zeros + order;
  if (rest + 1 > kMaxExpGolombWidth) {
    failed_ = malformed_ = true;
    return 0;
  }
  const std::uint64_t low = read_bits(rest);
  if (failed_) return 0;
  const std::uint64_t shifted = (std::uint64_t{1} << rest) | low;
  return shifted - (std::uint64_t{1} << order);
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
