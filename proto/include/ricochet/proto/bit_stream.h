#pragma once
/// Bit-level writer and reader for the packed snapshot payload (PROTOCOL.md Snapshots §bits).
///
/// Bits are written most significant first: the first bit written is bit 7 of byte 0. A value of
/// n bits is written from its bit n-1 down to bit 0. The last byte is padded with zero bits.
///
/// Variable-length integers use order-k Exp-Golomb codes: value v >= 0 is written as
/// z zero bits followed by the (z + k + 1)-bit binary of v + 2^k, where z = bit_width(v + 2^k) -
/// k - 1. Small values cost k + 1 bits; each doubling of v beyond 2^k costs 2 more bits.
/// Signed values are zig-zag mapped first (0, -1, 1, -2, 2 ... -> 0, 1, 2, 3, 4 ...).
///
/// The reader never reads past its input: a read beyond the end, or an Exp-Golomb prefix longer
/// than kMaxExpGolombWidth allows, sets a sticky failure flag and yields 0, so a decoder can read a
/// whole section and check failed() once.

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

namespace ricochet::proto {

/// Widest Exp-Golomb code body (prefix zeros + order + 1 bits) the reader accepts, so every
/// value read is below 2^42: headroom over every value the snapshot codec writes (< 2^33) and
/// no overflow when a decoder adds a delta to a 32-bit field. Longer codes are malformed.
inline constexpr int kMaxExpGolombWidth = 42;
/// Largest Exp-Golomb order the codec uses.
inline constexpr int kMaxExpGolombOrder = 31;

/// Maps a signed value to an unsigned one so that small magnitudes stay small.
constexpr std::uint64_t zigzag(std::int64_t value) {
  return (static_cast<std::uint64_t>(value) << 1) ^ static_cast<std::uint64_t>(value >> 63);
}
constexpr std::int64_t unzigzag(std::uint64_t value) {
  return static_cast<std::int64_t>(value >> 1) ^ -static_cast<std::int64_t>(value & 1);
}

/// Bits needed to write any value in [0, count - 1]; 0 when count <= 1.
constexpr int bits_for_count(std::uint64_t count) {
  int bits = 0;
  while (count > 1 && (std::uint64_t{1} << bits) < count) ++bits;
  return bits;
}

/// Bits the order-k Exp-Golomb code of `value` takes.
inline int exp_golomb_bits(std::uint64_t value, int order) {
  return 2 * std::bit_width(value + (std::uint64_t{1} << order)) - order - 1;
}

/// Writes the order-k Exp-Golomb code of `value` through `out.write_bits(value, bits)` (bits
/// 0..64): BitWriter's, or any writer that packs bits the same way.
template <class Writer>
void write_exp_golomb_to(Writer& out, std::uint64_t value, int order) {
  const std::uint64_t shifted = value + (std::uint64_t{1} << order);
  const int width = std::bit_width(shifted);
  const int zeros = width - order - 1;
  // The zeros are the leading bits of `shifted` written wider, when that fits one call.
  if (zeros + width <= 64) {
    out.write_bits(shifted, zeros + width);
    return;
  }
  out.write_bits(0, zeros);
  out.write_bits(shifted, width);
}

class BitWriter {
 public:
  /// Appends the low `bits` bits of value (0 <= bits <= 64), most significant first.
  void write_bits(std::uint64_t value, int bits) {
    if (bits <= 0) return;
    if (bits < 64) value &= (std::uint64_t{1} << bits) - 1;
    bit_count_ += static_cast<std::size_t>(bits);
    if (bits < free_bits_) {
      pending_ = (pending_ << bits) | value;
      free_bits_ -= bits;
      return;
    }
    // The accumulator fills up: its bits and value's top ones go out as 8 bytes.
    const int rest = bits - free_bits_;  // 0..63 bits of value left over
    const std::uint64_t word = (free_bits_ < 64 ? pending_ << free_bits_ : 0) | (value >> rest);
    flush_word(word);
    pending_ = rest == 0 ? 0 : value & ((std::uint64_t{1} << rest) - 1);
    free_bits_ = 64 - rest;
  }
  void write_bool(bool value) { write_bits(value ? 1 : 0, 1); }
  void write_exp_golomb(std::uint64_t value, int order) {
    write_exp_golomb_to(*this, value, order);
  }
  void write_signed_exp_golomb(std::int64_t value, int order) {
    write_exp_golomb(zigzag(value), order);
  }
  std::size_t bit_count() const { return bit_count_; }
  /// The bytes written so far; the last one zero-padded. Valid until the next write or clear.
  const std::vector<std::uint8_t>& bytes() const;
  void clear();

 private:
  /// Appends `word` as 8 bytes, most significant first.
  void flush_word(std::uint64_t word) {
    // bytes_ past flushed_bytes_ is scratch (what bytes() appended, or room from before a
    // clear); it grows by doubling, so a stream of n bytes resizes it O(log n) times.
    if (bytes_.size() < flushed_bytes_ + 8) {
      bytes_.resize(std::max<std::size_t>(64, 2 * bytes_.size()));
    }
    static_assert(std::endian::native == std::endian::little ||
                  std::endian::native == std::endian::big);
    if constexpr (std::endian::native == std::endian::little) word = __builtin_bswap64(word);
    std::memcpy(bytes_.data() + flushed_bytes_, &word, sizeof word);
    flushed_bytes_ += 8;
  }

  /// The first flushed_bytes_ bytes are written; bytes() appends the pending bits after them,
  /// which is why it is mutable (the bits written are the same either way).
  mutable std::vector<std::uint8_t> bytes_;
  std::size_t flushed_bytes_ = 0;
  std::uint64_t pending_ = 0;  ///< its low 64 - free_bits_ bits follow bytes_[flushed_bytes_ - 1]
  int free_bits_ = 64;         ///< 1..64 between calls
  std::size_t bit_count_ = 0;
};

class BitReader {
 public:
  explicit BitReader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}
  /// Reads `bits` bits (0 <= bits <= 64); 0 and failed() after the end of the input.
  std::uint64_t read_bits(int bits);
  bool read_bool() { return read_bits(1) != 0; }
  std::uint64_t read_exp_golomb(int order);
  std::int64_t read_signed_exp_golomb(int order) { return unzigzag(read_exp_golomb(order)); }
  bool failed() const { return failed_; }
  /// The failure came from an over-long Exp-Golomb code rather than the end of the input.
  bool malformed() const { return malformed_; }
  std::size_t bits_left() const { return failed_ ? 0 : bytes_.size() * 8 - position_; }
  /// True when every bit not yet read is zero (the padding of the last byte) and fewer than 8
  /// remain: the input held nothing more than what was read.
  bool only_padding_left() const;

 private:
  /// The next 64 bits from position_, zeros past the end of the input.
  std::uint64_t peek64() const;

  std::span<const std::uint8_t> bytes_;
  std::size_t position_ = 0;  ///< bits read
  bool failed_ = false;
  bool malformed_ = false;
};

inline std::uint64_t BitReader::peek64() const {
  const std::size_t byte = position_ / 8;
  const int shift = static_cast<int>(position_ % 8);
  std::uint64_t word = 0;
  if (byte + 8 <= bytes_.size()) {
    std::memcpy(&word, bytes_.data() + byte, sizeof word);
    if constexpr (std::endian::native == std::endian::little) word = __builtin_bswap64(word);
  } else {
    for (std::size_t k = byte; k < byte + 8; ++k) {
      word = (word << 8) | (k < bytes_.size() ? bytes_[k] : 0u);
    }
  }
  if (shift != 0) {
    const std::uint64_t next = byte + 8 < bytes_.size() ? bytes_[byte + 8] : 0u;
    word = (word << shift) | (next >> (8 - shift));
  }
  return word;
}

inline std::uint64_t BitReader::read_bits(int bits) {
  if (failed_ || static_cast<std::size_t>(bits) > bytes_.size() * 8 - position_) {
    failed_ = true;
    return 0;
  }
  if (bits == 0) return 0;
  const std::uint64_t value = peek64() >> (64 - bits);
  position_ += static_cast<std::size_t>(bits);
  return value;
}

inline std::uint64_t BitReader::read_exp_golomb(int order) {
  if (failed_) return 0;
  const std::size_t left = bytes_.size() * 8 - position_;
  // The zeros before the leading 1: more than `most_zeros` make the code malformed. A code
  // that ends before its 1 is truncated, and malformed too once the zeros read and the one
  // missing bit are more than `most_zeros` (as a reader taking one bit at a time finds it).
  const std::int64_t most_zeros = kMaxExpGolombWidth - order - 1;
  const std::uint64_t next = peek64();
  const std::size_t zeros = std::min<std::size_t>(next == 0 ? 64 : std::countl_zero(next), left);
  if (zeros == left) {
    failed_ = true;
    malformed_ = static_cast<std::int64_t>(left) >= most_zeros;
    return 0;
  }
  if (static_cast<std::int64_t>(zeros) > most_zeros) {
    failed_ = malformed_ = true;
    return 0;
  }
  // The code is the zeros, then v + 2^order in zeros + order + 1 bits.
  const std::size_t width = 2 * zeros + static_cast<std::size_t>(order) + 1;
  if (width > left) {
    failed_ = true;
    return 0;
  }
  const std::uint64_t base = std::uint64_t{1} << order;
  if (width <= 64) {  // all of it in the bits peeked
    position_ += width;
    return (next >> (64 - width)) - base;
  }
  position_ += zeros + 1;  // the zeros and the leading 1; the rest follows
  const int rest = static_cast<int>(zeros) + order;
  return ((std::uint64_t{1} << rest) | read_bits(rest)) - base;
}

}  // namespace ricochet::proto
