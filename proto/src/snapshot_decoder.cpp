/// SnapshotDecoder: validates a snapshot against its baseline and rebuilds the client's entity
/// set (PROTOCOL.snapshot.md §stream, §rejections). Nothing is asserted about the input: every
/// count, index, code and value is checked, and a refusal changes nothing.

#include <cassert>

#include "ricochet/proto/bit_stream.h"
#include "ricochet/proto/snapshot_codec.h"
#include "snapshot_layout.h"

namespace ricochet::proto {

namespace layout = snapshot_layout;

const char* name(SnapshotRejection reason) {
  switch (reason) {
    case SnapshotRejection::Oversized:
      return "oversized";
    case SnapshotRejection::Stale:
      return "stale";
    case SnapshotRejection::BaselineAfterTick:
      return "baseline_after_tick";
    case SnapshotRejection::UnknownBaseline:
      return "unknown_baseline";
    case SnapshotRejection::Truncated:
      return "truncated";
    case SnapshotRejection::BadCode:
      return "bad_code";
    case SnapshotRejection::RemovedOutOfRange:
      return "removed_out_of_range";
    case SnapshotRejection::IdOutOfOrder:
      return "id_out_of_order";
    case SnapshotRejection::TooManyEntities:
      return "too_many_entities";
    case SnapshotRejection::ChangedOutOfRange:
      return "changed_out_of_range";
    case SnapshotRejection::EmptyChange:
      return "empty_change";
    case SnapshotRejection::ValueOutOfRange:
      return "value_out_of_range";
    case SnapshotRejection::TrailingBits:
      return "trailing_bits";
    case SnapshotRejection::kCount:
      break;
  }
  return "unknown";
}

std::string SnapshotDecoderOptions::validate() const {
  if (ring_size < 2 || ring_size > 1024) {
    return "ring_size must be 2..1024, got " + std::to_string(ring_size);
  }
  if (max_entities == 0) return "max_entities must be > 0, got 0";
  return {};
}

SnapshotDecoder::SnapshotDecoder(QuantizationSpec spec, SnapshotDecoderOptions options)
    : spec_(spec), options_(options), ring_(options.ring_size) {
  assert(spec_.validate().empty() && options_.validate().empty());
}

namespace {

struct Refusal {
  SnapshotRejection reason;
  std::string message;
};

/// A reader failure as a refusal: an over-long code, or the stream's end inside `what`.
Refusal reader_refusal(const BitReader& in, const char* what) {
  if (in.malformed()) {
    return {SnapshotRejection::BadCode,
            std::string("expected an Exp-Golomb code of at most 42 bits in ") + what +
                ", got a longer prefix"};
  }
  return {SnapshotRejection::Truncated,
          std::string("expected more bits in ") + what + ", got the end of the stream"};
}

}  // namespace

SnapshotDecodeResult SnapshotDecoder::decode(const wire::Snapshot& in) {
  SnapshotDecodeResult result;
  result.tick = in.tick();
  auto refuse = [&](Refusal refusal) {
    ++rejections_[static_cast<std::size_t>(refusal.reason)];
    result.ok = false;
    result.reason = refusal.reason;
    result.message = std::move(refusal.message);
    return result;
  };

  const std::string& bytes = in.entities();
  if (bytes.size() > kMaxSnapshotStreamBytes) {
    return refuse({SnapshotRejection::Oversized, "expected an entity stream of at most " +
                                                     std::to_string(kMaxSnapshotStreamBytes) +
                                                     " bytes, got " +
                                                     std::to_string(bytes.size())});
  }
  if (has_newest_ && in.tick() <= newest_tick_) {
    return refuse({SnapshotRejection::Stale, "expected a tick after " +
                                                 std::to_string(newest_tick_) + ", got " +
                                                 std::to_string(in.tick())});
  }
  if (in.baseline_age() > in.tick()) {
    return refuse({SnapshotRejection::BaselineAfterTick, "expected baseline_age <= tick " +
                                                             std::to_string(in.tick()) + ", got " +
                                                             std::to_string(in.baseline_age())});
  }
  std::span<const QuantizedEntity> baseline;
  if (in.baseline_age() != 0) {
    const std::uint32_t baseline_tick = in.tick() - in.baseline_age();
    const Decoded& entry = ring_[baseline_tick % ring_.size()];
    if (!entry.valid || entry.tick != baseline_tick) {
      return refuse({SnapshotRejection::UnknownBaseline,
                     "expected a baseline tick among the last " + std::to_string(ring_.size()) +
                         " decoded, got " + std::to_string(baseline_tick)});
    }
    baseline = entry.view;
  }

  const layout::FieldWidths widths(spec_);
  BitReader reader(std::span<const std::uint8_t>(
      reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
  auto read_count = [&reader](std::uint64_t& count) {
    count = reader.read_exp_golomb(0);
    return !reader.failed();
  };

  // Removals: ascending indices into the baseline.
  std::uint64_t removed_count = 0;
  if (!read_count(removed_count)) {
    return refuse(reader_refusal(reader, "the removal count"));
  }
  if (removed_count > baseline.size()) {
    return refuse({SnapshotRejection::RemovedOutOfRange,
                   "expected at most " + std::to_string(baseline.size()) +
                       " removals (the baseline's entities), got " +
                       std::to_string(removed_count)});
  }
  std::vector<std::uint8_t> removed(baseline.size(), 0);
  if (removed_count > 0) {
    const int order = static_cast<int>(reader.read_bits(layout::kOrderBits));
    std::uint64_t index = 0;
    for (std::uint64_t k = 0; k < removed_count; ++k) {
      const std::uint64_t gap = layout::read_code(reader, order);
      if (reader.failed()) return refuse(reader_refusal(reader, "a removal"));
      index += gap + (k == 0 ? 0 : 1);
      if (index >= baseline.size()) {
        return refuse({SnapshotRejection::RemovedOutOfRange, "expected a removal index below " +
                                                                 std::to_string(baseline.size()) +
                                                                 ", got " + std::to_string(index)});
      }
      removed[index] = 1;
    }
  }
  const std::uint64_t kept_count = baseline.size() - removed_count;

  // Additions: ascending ids, each with its absolute state.
  std::uint64_t added_count = 0;
  if (!read_count(added_count)) {
    return refuse(reader_refusal(reader, "the addition count"));
  }
  if (kept_count + added_count > options_.max_entities) {
    return refuse({SnapshotRejection::TooManyEntities,
                   "expected at most " + std::to_string(options_.max_entities) + " entities, got " +
                       std::to_string(kept_count + added_count)});
  }
  std::vector<QuantizedEntity> added;
  if (added_count > 0) {
    if (added_count > reader.bits_left()) {
      return refuse(reader_refusal(reader, "the additions"));
    }
    added.resize(added_count);
    const int order = static_cast<int>(reader.read_bits(layout::kOrderBits));
    std::uint64_t id = 0;
    for (std::uint64_t k = 0; k < added_count; ++k) {
      const std::uint64_t gap = layout::read_code(reader, order);
      if (reader.failed()) return refuse(reader_refusal(reader, "an addition's id"));
      id += gap + (k == 0 ? 0 : 1);
      if (id > 0xFFFFFFFFu) {
        return refuse({SnapshotRejection::IdOutOfOrder,
                       "expected a new entity id below 2^32, got " + std::to_string(id)});
      }
      added[k].id = static_cast<std::uint32_t>(id);
      const bool in_range = layout::read_absolute(reader, widths, added[k]);
      if (reader.failed()) return refuse(reader_refusal(reader, "a new entity's state"));
      if (!in_range) {
        return refuse({SnapshotRejection::ValueOutOfRange,
                       "expected new entity " + std::to_string(id) +
                           " within the spec's ranges, got a value outside"});
      }
    }
  }

  // The kept baseline entities, then the changes applied to them.
  scratch_.clear();
  scratch_.reserve(kept_count + added_count);
  for (std::size_t k = 0; k < baseline.size(); ++k) {
    if (!removed[k]) scratch_.push_back(baseline[k]);
  }
  std::uint64_t changed_count = 0;
  if (!read_count(changed_count)) {
    return refuse(reader_refusal(reader, "the change count"));
  }
  if (changed_count > kept_count) {
    return refuse({SnapshotRejection::ChangedOutOfRange,
                   "expected at most " + std::to_string(kept_count) +
                       " changes (the kept entities), got " + std::to_string(changed_count)});
  }
  if (changed_count > 0) {
    layout::DeltaOrders orders;
    auto read_order = [&reader] { return static_cast<int>(reader.read_bits(layout::kOrderBits)); };
    orders.gap = read_order();
    for (int& order : orders.velocity) order = read_order();
    for (int& order : orders.position) order = read_order();
    orders.orientation = read_order();
    const layout::Prediction prediction = layout::make_prediction(in.baseline_age(), spec_);
    std::uint64_t index = 0;
    std::uint8_t previous_mask = layout::kInitialFieldMask;
    for (std::uint64_t k = 0; k < changed_count; ++k) {
      const std::uint64_t gap = layout::read_code(reader, orders.gap);
      if (reader.failed()) return refuse(reader_refusal(reader, "a change's gap"));
      index += gap + (k == 0 ? 0 : 1);
      if (index >= kept_count) {
        return refuse({SnapshotRejection::ChangedOutOfRange, "expected a change index below " +
                                                                 std::to_string(kept_count) +
                                                                 ", got " + std::to_string(index)});
      }
      const layout::DeltaStatus status =
          layout::read_delta(reader, orders, widths, prediction, previous_mask, scratch_[index]);
      if (reader.failed()) return refuse(reader_refusal(reader, "a change"));
      if (status == layout::DeltaStatus::EmptyChange) {
        return refuse({SnapshotRejection::EmptyChange, "expected a change to entity " +
                                                           std::to_string(scratch_[index].id) +
                                                           ", got its baseline state again"});
      }
      if (status == layout::DeltaStatus::OutOfRange) {
        return refuse({SnapshotRejection::ValueOutOfRange,
                       "expected entity " + std::to_string(scratch_[index].id) +
                           " within the spec's ranges after its delta, got a value outside"});
      }
    }
  }
  if (!reader.only_padding_left()) {
    return refuse(
        {SnapshotRejection::TrailingBits, "expected only zero padding after the last change, got " +
                                              std::to_string(reader.bits_left()) + " more bits"});
  }

  // Merge the additions in by id; an id already held is refused.
  const std::size_t kept_end = scratch_.size();
  scratch_.insert(scratch_.end(), added.begin(), added.end());
  std::vector<QuantizedEntity> view;
  view.reserve(scratch_.size());
  std::size_t a = kept_end, b = 0;
  while (b < kept_end || a < scratch_.size()) {
    if (a == scratch_.size() || (b < kept_end && scratch_[b].id < scratch_[a].id)) {
      view.push_back(scratch_[b++]);
    } else if (b == kept_end || scratch_[a].id < scratch_[b].id) {
      view.push_back(scratch_[a++]);
    } else {
      return refuse(
          {SnapshotRejection::IdOutOfOrder, "expected new entity ids not already held, got " +
                                                std::to_string(scratch_[a].id) + " again"});
    }
  }

  Decoded& entry = ring_[in.tick() % ring_.size()];
  entry.valid = true;
  entry.tick = in.tick();
  entry.view.swap(view);
  has_newest_ = true;
  newest_tick_ = in.tick();
  ++accepted_;
  result.ok = true;
  result.entities = entry.view;
  return result;
}

}  // namespace ricochet::proto
