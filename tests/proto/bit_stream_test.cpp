#include "ricochet/proto/bit_stream.h"

#include <gtest/gtest.h>

#include <random>

namespace ricochet::proto::bit_stream_test {
namespace {

TEST(BitStream, WritesMostSignificantBitFirstAndPadsWithZeros) {
  BitWriter writer;
  writer.write_bits(0b101, 3);
  writer.write_bits(0b1, 1);
  writer.write_bits(0b11, 2);
  ASSERT_EQ(writer.bit_count(), 6u);
  ASSERT_EQ(writer.bytes().size(), 1u);
  EXPECT_EQ(writer.bytes()[0], 0b10111100);
}

TEST(BitStream, ExpGolombOrderZeroMatchesTheTextbookCodes) {
  // 0 -> 1, 1 -> 010, 2 -> 011, 3 -> 00100.
  BitWriter writer;
  for (const std::uint64_t value : {0u, 1u, 2u, 3u}) writer.write_exp_golomb(value, 0);
  EXPECT_EQ(writer.bit_count(), 1u + 3 + 3 + 5);
  EXPECT_EQ(writer.bytes()[0], 0b10100110);
  EXPECT_EQ(writer.bytes()[1], 0b01000000);
  EXPECT_EQ(exp_golomb_bits(0, 0), 1);
  EXPECT_EQ(exp_golomb_bits(3, 0), 5);
  EXPECT_EQ(exp_golomb_bits(0, 4), 5);
  EXPECT_EQ(exp_golomb_bits(15, 4), 5);
  EXPECT_EQ(exp_golomb_bits(16, 4), 7);
}

TEST(BitStream, RandomMixOfFieldsReadsBackExactly) {
  std::mt19937_64 random(7);
  struct Field {
    int kind;  // 0 raw, 1 unsigned Exp-Golomb, 2 signed
    int width_or_order;
    std::uint64_t value;
  };
  std::vector<Field> fields;
  BitWriter writer;
  for (int i = 0; i < 5000; ++i) {
    Field field{static_cast<int>(random() % 3), 0, 0};
    if (field.kind == 0) {
      field.width_or_order = static_cast<int>(random() % 65);
      field.value = field.width_or_order == 64
                        ? random()
                        : random() & ((std::uint64_t{1} << field.width_or_order) - 1);
      writer.write_bits(field.value, field.width_or_order);
    } else {
      field.width_or_order = static_cast<int>(random() % 20);
      field.value = random() >> (28 + random() % 36);
      if (field.kind == 1) {
        const std::size_t before = writer.bit_count();
        writer.write_exp_golomb(field.value, field.width_or_order);
        ASSERT_EQ(writer.bit_count() - before,
                  static_cast<std::size_t>(exp_golomb_bits(field.value, field.width_or_order)));
      } else {
        writer.write_signed_exp_golomb(unzigzag(field.value), field.width_or_order);
      }
    }
    fields.push_back(field);
  }
  BitReader reader(writer.bytes());
  for (const Field& field : fields) {
    if (field.kind == 0) {
      ASSERT_EQ(reader.read_bits(field.width_or_order), field.value);
    } else if (field.kind == 1) {
      ASSERT_EQ(reader.read_exp_golomb(field.width_or_order), field.value);
    } else {
      ASSERT_EQ(reader.read_signed_exp_golomb(field.width_or_order), unzigzag(field.value));
    }
  }
  EXPECT_FALSE(reader.failed());
  EXPECT_TRUE(reader.only_padding_left());
}

TEST(BitStream, ZigzagKeepsSmallMagnitudesSmall) {
  EXPECT_EQ(zigzag(0), 0u);
  EXPECT_EQ(zigzag(-1), 1u);
  EXPECT_EQ(zigzag(1), 2u);
  EXPECT_EQ(zigzag(-2), 3u);
  for (const std::int64_t v :
       {std::int64_t{-5000000000}, std::int64_t{123}, INT64_MIN, INT64_MAX}) {
    EXPECT_EQ(unzigzag(zigzag(v)), v);
  }
}

TEST(BitStream, ReadingPastTheEndFailsAndStaysFailed) {
  const std::vector<std::uint8_t> bytes{0xFF};
  BitReader reader(bytes);
  EXPECT_EQ(reader.read_bits(6), 0x3Fu);
  EXPECT_EQ(reader.read_bits(3), 0u);
  EXPECT_TRUE(reader.failed());
  EXPECT_FALSE(reader.malformed());
  EXPECT_EQ(reader.read_bits(1), 0u);
  EXPECT_TRUE(reader.failed());
  EXPECT_FALSE(reader.only_padding_left());
}

TEST(BitStream, AnOverlongExpGolombPrefixIsMalformedNotAnOverflow) {
  const std::vector<std::uint8_t> zeros(16, 0);
  BitReader reader(zeros);
  EXPECT_EQ(reader.read_exp_golomb(0), 0u);
  EXPECT_TRUE(reader.failed());
  EXPECT_TRUE(reader.malformed());

  // A 42-bit code body is the widest accepted: 2^42 - 2 reads back, 2^42 - 1 is malformed.
  BitWriter widest;
  widest.write_exp_golomb((std::uint64_t{1} << 42) - 2, 0);
  BitReader widest_reader(widest.bytes());
  EXPECT_EQ(widest_reader.read_exp_golomb(0), (std::uint64_t{1} << 42) - 2);
  EXPECT_FALSE(widest_reader.failed());
  BitWriter wider;
  wider.write_exp_golomb((std::uint64_t{1} << 42) - 1, 0);
  BitReader wider_reader(wider.bytes());
  wider_reader.read_exp_golomb(0);
  EXPECT_TRUE(wider_reader.malformed());
}

TEST(BitStream, PaddingMustBeZero) {
  const std::vector<std::uint8_t> bytes{0b10000001};
  BitReader reader(bytes);
  EXPECT_TRUE(reader.read_bool());
  EXPECT_FALSE(reader.only_padding_left());
  const std::vector<std::uint8_t> clean{0b10000000};
  BitReader clean_reader(clean);
  EXPECT_TRUE(clean_reader.read_bool());
  EXPECT_TRUE(clean_reader.only_padding_left());
}

/// The reader as first written, one bit at a time: the word-at-a-time BitReader must read the
/// same values and fail the same way on any input.
class BitByBitReader {
 public:
  explicit BitByBitReader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}
  std::uint64_t read_bits(int bits) {
    if (failed_ || static_cast<std::size_t>(bits) > bytes_.size() * 8 - position_) {
      failed_ = true;
      return 0;
    }
    std::uint64_t value = 0;
    for (int i = 0; i < bits; ++i, ++position_) {
      value = (value << 1) | ((bytes_[position_ / 8] >> (7 - position_ % 8)) & 1u);
    }
    return value;
  }
  std::uint64_t read_exp_golomb(int order) {
    int zeros = 0;
    while (!failed_ && read_bits(1) == 0) {
      if (++zeros + order + 1 > kMaxExpGolombWidth) failed_ = malformed_ = true;
    }
    if (failed_) return 0;
    const int rest = zeros + order;
    if (rest + 1 > kMaxExpGolombWidth) {
      failed_ = malformed_ = true;
      return 0;
    }
    const std::uint64_t low = read_bits(rest);
    if (failed_) return 0;
    return ((std::uint64_t{1} << rest) | low) - (std::uint64_t{1} << order);
  }
  bool failed() const { return failed_; }
  bool malformed() const { return malformed_; }
  std::size_t bits_left() const { return failed_ ? 0 : bytes_.size() * 8 - position_; }

 private:
  std::span<const std::uint8_t> bytes_;
  std::size_t position_ = 0;
  bool failed_ = false;
  bool malformed_ = false;
};

TEST(BitStream, ReaderMatchesTheBitByBitReaderOnAnyInput) {
  std::mt19937_64 random(19);
  for (int trial = 0; trial < 3000; ++trial) {
    // Sparse bytes make long runs of zeros (long and over-long Exp-Golomb prefixes).
    std::vector<std::uint8_t> bytes(random() % 24);
    for (std::uint8_t& byte : bytes) {
      byte = random() % 3 == 0 ? static_cast<std::uint8_t>(random()) : 0;
    }
    BitReader reader(bytes);
    BitByBitReader expected(bytes);
    for (int step = 0; step < 40; ++step) {
      if (random() % 2 == 0) {
        const int bits = static_cast<int>(random() % 65);
        ASSERT_EQ(reader.read_bits(bits), expected.read_bits(bits)) << trial << "/" << step;
      } else {
        const int order = static_cast<int>(random() % 32);
        ASSERT_EQ(reader.read_exp_golomb(order), expected.read_exp_golomb(order))
            << trial << "/" << step;
      }
      ASSERT_EQ(reader.failed(), expected.failed()) << trial << "/" << step;
      ASSERT_EQ(reader.malformed(), expected.malformed()) << trial << "/" << step;
      ASSERT_EQ(reader.bits_left(), expected.bits_left()) << trial << "/" << step;
    }
  }
}

TEST(BitStream, BitsForCount) {
  EXPECT_EQ(bits_for_count(0), 0);
  EXPECT_EQ(bits_for_count(1), 0);
  EXPECT_EQ(bits_for_count(2), 1);
  EXPECT_EQ(bits_for_count(128001), 17);
  EXPECT_EQ(bits_for_count(65536), 16);
}

}  // namespace
}  // namespace ricochet::proto::bit_stream_test
