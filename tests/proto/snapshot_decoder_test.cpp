/// The decoder refuses every malformed snapshot with its reason, counts it, and stays as it was.
/// The streams are written by hand after PROTOCOL.md Snapshots §stream.

#include <gtest/gtest.h>

#include <random>
#include <string>

#include "ricochet/proto/bit_stream.h"
#include "ricochet/proto/snapshot_codec.h"
#include "snapshot_test_world.h"

namespace ricochet::proto::snapshot_decoder_test {
namespace {

using test::test_spec;

constexpr std::array<float, 3> kOrigin{0, 0, 0};

wire::Snapshot make_snapshot(std::uint32_t tick, std::uint32_t baseline_age,
                             const BitWriter& bits) {
  wire::Snapshot snapshot;
  snapshot.set_tick(tick);
  snapshot.set_baseline_age(baseline_age);
  snapshot.set_entities(bits.bytes().data(), bits.bytes().size());
  return snapshot;
}

/// A decoder holding tick 10 with three entities (ids 5, 6, 9) at rest at the bounds' minimum.
class Decoder : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const std::uint32_t id : {5u, 6u, 9u}) {
      QuantizedEntity entity;
      entity.id = id;
      baseline_.push_back(entity);
    }
    SnapshotEncoder encoder(spec_);
    wire::Snapshot snapshot;
    encoder.encode(10, baseline_, kOrigin, 1100, snapshot);
    ASSERT_TRUE(decoder_.decode(snapshot).ok);
  }

  /// Decodes and expects a refusal for `reason`, counted, with the decoder unchanged.
  void expect_refused(const wire::Snapshot& snapshot, SnapshotRejection reason) {
    const auto before = decoder_.rejections()[static_cast<std::size_t>(reason)];
    const SnapshotDecodeResult result = decoder_.decode(snapshot);
    EXPECT_FALSE(result.ok);
    EXPECT_EQ(result.reason, reason) << "got " << name(result.reason) << ": " << result.message;
    EXPECT_FALSE(result.message.empty());
    EXPECT_EQ(decoder_.rejections()[static_cast<std::size_t>(reason)], before + 1);
    EXPECT_EQ(decoder_.newest_tick(), 10u);
  }

  /// Counts and orders of an otherwise empty delta against tick 10.
  static void write_counts(BitWriter& bits, std::uint64_t removed, std::uint64_t added,
                           std::uint64_t changed) {
    bits.write_exp_golomb(removed, 0);
    bits.write_exp_golomb(added, 0);
    bits.write_exp_golomb(changed, 0);
  }

  QuantizationSpec spec_ = test_spec();
  SnapshotDecoder decoder_{spec_};
  std::vector<QuantizedEntity> baseline_;
};

TEST_F(Decoder, AcceptsAHandWrittenDeltaThatMovesOneEntity) {
  BitWriter bits;
  bits.write_exp_golomb(0, 0);                        // no removals
  bits.write_exp_golomb(0, 0);                        // no additions
  bits.write_exp_golomb(1, 0);                        // one change
  for (int k = 0; k < 8; ++k) bits.write_bits(0, 5);  // orders 0
  bits.write_exp_golomb(2, 0);                        // the third kept entity, id 9
  bits.write_bits(0, 1);                              // a new mask:
  bits.write_bits(0b0100, 4);                         // position only
  bits.write_signed_exp_golomb(7, 0);                 // x + 7 mm
  bits.write_signed_exp_golomb(0, 0);
  bits.write_signed_exp_golomb(3, 0);
  const SnapshotDecodeResult result = decoder_.decode(make_snapshot(11, 1, bits));
  ASSERT_TRUE(result.ok) << result.message;
  ASSERT_EQ(result.entities.size(), 3u);
  EXPECT_EQ(result.entities[2].id, 9u);
  EXPECT_EQ(result.entities[2].position, (std::array<std::uint32_t, 3>{7, 0, 3}));
  EXPECT_EQ(decoder_.newest_tick(), 11u);
}

TEST_F(Decoder, RefusesAnOversizedStream) {
  wire::Snapshot snapshot;
  snapshot.set_tick(11);
  snapshot.set_baseline_age(1);
  snapshot.set_entities(std::string(kMaxSnapshotStreamBytes + 1, '\0'));
  expect_refused(snapshot, SnapshotRejection::Oversized);
}

TEST_F(Decoder, RefusesStaleAndDuplicateTicks) {
  BitWriter bits;
  write_counts(bits, 0, 0, 0);
  expect_refused(make_snapshot(10, 0, bits), SnapshotRejection::Stale);
  expect_refused(make_snapshot(9, 0, bits), SnapshotRejection::Stale);
}

TEST_F(Decoder, RefusesABaselineBeforeTickZeroOrNotHeld) {
  BitWriter bits;
  write_counts(bits, 0, 0, 0);
  expect_refused(make_snapshot(12, 13, bits), SnapshotRejection::BaselineAfterTick);
  expect_refused(make_snapshot(12, 1, bits), SnapshotRejection::UnknownBaseline);  // tick 11
  expect_refused(make_snapshot(10 + 64, 65, bits), SnapshotRejection::UnknownBaseline);
}

TEST_F(Decoder, RefusesTruncatedStreams) {
  expect_refused(make_snapshot(11, 1, BitWriter{}), SnapshotRejection::Truncated);
  BitWriter bits;
  bits.write_exp_golomb(0, 0);
  bits.write_exp_golomb(0, 0);
  bits.write_exp_golomb(1, 0);
  bits.write_bits(0, 5);  // orders cut short: only one of eight
  expect_refused(make_snapshot(11, 1, bits), SnapshotRejection::Truncated);
}

TEST_F(Decoder, RefusesOverlongCodes) {
  BitWriter bits;
  bits.write_bits(0, 60);
  bits.write_bits(1, 1);
  expect_refused(make_snapshot(11, 1, bits), SnapshotRejection::BadCode);
}

TEST_F(Decoder, RefusesRemovalsBeyondTheBaseline) {
  BitWriter too_many;
  write_counts(too_many, 4, 0, 0);
  expect_refused(make_snapshot(11, 1, too_many), SnapshotRejection::RemovedOutOfRange);
  BitWriter past_end;
  past_end.write_exp_golomb(2, 0);
  past_end.write_bits(0, 5);
  past_end.write_exp_golomb(1, 0);  // index 1
  past_end.write_exp_golomb(1, 0);  // index 3: past the three entities
  past_end.write_exp_golomb(0, 0);
  past_end.write_exp_golomb(0, 0);
  expect_refused(make_snapshot(11, 1, past_end), SnapshotRejection::RemovedOutOfRange);
}

/// A new entity at rest with position (x, 0, 0) in raw bits; `x_raw` may be out of range.
void write_new_entity(BitWriter& bits, std::uint64_t id_gap, std::uint64_t x_raw,
                      const QuantizationSpec& spec) {
  bits.write_exp_golomb(id_gap, 0);
  bits.write_bits(x_raw, bits_for_count(spec.position_steps(0)));
  bits.write_bits(0, bits_for_count(spec.position_steps(1)));
  bits.write_bits(0, bits_for_count(spec.position_steps(2)));
  bits.write_bool(false);  // velocity zero
  bits.write_bool(false);  // identity
  bits.write_bool(false);  // no flags
}

TEST_F(Decoder, RefusesANewEntityWithAnIdAlreadyHeld) {
  BitWriter bits;
  bits.write_exp_golomb(0, 0);
  bits.write_exp_golomb(1, 0);
  bits.write_bits(0, 5);
  write_new_entity(bits, 6, 0, spec_);  // id 6 is in the baseline
  bits.write_exp_golomb(0, 0);
  expect_refused(make_snapshot(11, 1, bits), SnapshotRejection::IdOutOfOrder);
}

TEST_F(Decoder, RefusesNewEntityIdsBeyond32Bits) {
  BitWriter bits;
  bits.write_exp_golomb(0, 0);
  bits.write_exp_golomb(2, 0);
  bits.write_bits(0, 5);
  write_new_entity(bits, 0xFFFFFFF0u, 0, spec_);
  write_new_entity(bits, 0x20, 0, spec_);
  bits.write_exp_golomb(0, 0);
  expect_refused(make_snapshot(11, 1, bits), SnapshotRejection::IdOutOfOrder);
}

TEST_F(Decoder, RefusesMoreEntitiesThanItsLimit) {
  SnapshotDecoderOptions options;
  options.max_entities = 2;
  SnapshotDecoder small(spec_, options);
  BitWriter bits;
  bits.write_exp_golomb(0, 0);
  bits.write_exp_golomb(3, 0);
  bits.write_bits(0, 5);
  for (int k = 0; k < 3; ++k) write_new_entity(bits, 0, 0, spec_);
  bits.write_exp_golomb(0, 0);
  const SnapshotDecodeResult result = small.decode(make_snapshot(1, 0, bits));
  EXPECT_FALSE(result.ok);
  EXPECT_EQ(result.reason, SnapshotRejection::TooManyEntities);
  EXPECT_FALSE(small.has_snapshot());
}

TEST_F(Decoder, RefusesChangesBeyondTheKeptEntities) {
  BitWriter bits;
  bits.write_exp_golomb(1, 0);
  bits.write_bits(0, 5);
  bits.write_exp_golomb(0, 0);  // remove index 0, so two are kept
  bits.write_exp_golomb(0, 0);
  bits.write_exp_golomb(3, 0);  // three changes
  expect_refused(make_snapshot(11, 1, bits), SnapshotRejection::ChangedOutOfRange);
  BitWriter gap;
  write_counts(gap, 0, 0, 1);
  for (int k = 0; k < 8; ++k) gap.write_bits(0, 5);
  gap.write_exp_golomb(3, 0);  // index 3 of three
  gap.write_bits(0, 1);        // a new mask:
  gap.write_bits(0b0001, 4);
  gap.write_bits(1, 8);
  expect_refused(make_snapshot(11, 1, gap), SnapshotRejection::ChangedOutOfRange);
}

TEST_F(Decoder, RefusesAChangeThatChangesNothing) {
  BitWriter bits;
  write_counts(bits, 0, 0, 1);
  for (int k = 0; k < 8; ++k) bits.write_bits(0, 5);
  bits.write_exp_golomb(0, 0);
  bits.write_bits(0, 1);  // a new mask:
  bits.write_bits(0, 4);
  expect_refused(make_snapshot(11, 1, bits), SnapshotRejection::EmptyChange);
}

TEST_F(Decoder, RefusesValuesOutsideTheSpec) {
  BitWriter new_entity;
  new_entity.write_exp_golomb(0, 0);
  new_entity.write_exp_golomb(1, 0);
  new_entity.write_bits(0, 5);
  write_new_entity(new_entity, 20, spec_.position_steps(0), spec_);  // one past the last step
  new_entity.write_exp_golomb(0, 0);
  expect_refused(make_snapshot(11, 1, new_entity), SnapshotRejection::ValueOutOfRange);

  BitWriter below_zero;
  write_counts(below_zero, 0, 0, 1);
  for (int k = 0; k < 8; ++k) below_zero.write_bits(0, 5);
  below_zero.write_exp_golomb(0, 0);
  below_zero.write_bits(0, 1);  // a new mask:
  below_zero.write_bits(0b0100, 4);
  below_zero.write_signed_exp_golomb(-1, 0);  // x was 0
  below_zero.write_signed_exp_golomb(0, 0);
  below_zero.write_signed_exp_golomb(0, 0);
  expect_refused(make_snapshot(11, 1, below_zero), SnapshotRejection::ValueOutOfRange);

  BitWriter too_fast;
  write_counts(too_fast, 0, 0, 1);
  for (int k = 0; k < 8; ++k) too_fast.write_bits(0, 5);
  too_fast.write_exp_golomb(0, 0);
  too_fast.write_bits(0, 1);  // a new mask:
  too_fast.write_bits(0b1000, 4);
  too_fast.write_signed_exp_golomb(spec_.velocity_limit() + 1, 0);
  too_fast.write_signed_exp_golomb(0, 0);
  too_fast.write_signed_exp_golomb(0, 0);
  expect_refused(make_snapshot(11, 1, too_fast), SnapshotRejection::ValueOutOfRange);
}

TEST_F(Decoder, RefusesBitsAfterTheLastField) {
  BitWriter bits;
  write_counts(bits, 0, 0, 0);
  bits.write_bits(1, 1);  // inside the padding
  expect_refused(make_snapshot(11, 1, bits), SnapshotRejection::TrailingBits);
  BitWriter extra_byte;
  write_counts(extra_byte, 0, 0, 0);
  extra_byte.write_bits(0, 13);  // a whole zero byte more than needed
  expect_refused(make_snapshot(11, 1, extra_byte), SnapshotRejection::TrailingBits);
}

TEST_F(Decoder, StillDecodesAfterRefusals) {
  BitWriter bad;
  bad.write_bits(0, 60);
  EXPECT_FALSE(decoder_.decode(make_snapshot(11, 1, bad)).ok);
  BitWriter good;
  write_counts(good, 0, 0, 0);
  const SnapshotDecodeResult result = decoder_.decode(make_snapshot(11, 1, good));
  ASSERT_TRUE(result.ok) << result.message;
  EXPECT_EQ(std::vector<QuantizedEntity>(result.entities.begin(), result.entities.end()),
            baseline_);
}

TEST_F(Decoder, RandomBytesAreRefusedOrDecodedNeverTrusted) {
  std::mt19937 random(21);
  std::uint64_t refused = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    std::string bytes(random() % 40, '\0');
    for (char& c : bytes) c = static_cast<char>(random());
    wire::Snapshot snapshot;
    snapshot.set_tick(11 + random() % 3);
    snapshot.set_baseline_age(random() % 3);
    snapshot.set_entities(bytes);
    SnapshotDecoder copy = decoder_;
    const SnapshotDecodeResult result = copy.decode(snapshot);
    refused += !result.ok;
    if (result.ok) {
      for (const QuantizedEntity& e : result.entities) ASSERT_TRUE(in_range(e, spec_));
      for (std::size_t k = 1; k < result.entities.size(); ++k) {
        ASSERT_LT(result.entities[k - 1].id, result.entities[k].id);
      }
    }
  }
  EXPECT_GT(refused, 10000u);
}

TEST(SnapshotRejectionNames, EveryReasonHasAName) {
  for (std::size_t k = 0; k < static_cast<std::size_t>(SnapshotRejection::kCount); ++k) {
    EXPECT_STRNE(name(static_cast<SnapshotRejection>(k)), "unknown");
  }
}

}  // namespace
}  // namespace ricochet::proto::snapshot_decoder_test
