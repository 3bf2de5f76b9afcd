/// SnapshotDecoder: validates a snapshot against its baseline and rebuilds the client's entity
/// set (PROTOCOL.md Snapshots §stream, §rejections). Nothing is asserted about the input: every
/// count, index, code and value is checked, and a refusal changes nothing.

#include <cassert>
#include <optional>

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
using MaybeRefusal = std::optional<Refusal>;

/// A reader failure as a refusal: an over-long code, or the stream's end inside `what`.
Refusal reader_refusal(const BitReader& in, const char* what) {
  if (in.malformed()) {
    return {SnapshotRejection::BadCode, std::string("expected an Exp-Golomb code of at most 42 "
                                                    "bits in ") +
                                            what + ", got a longer prefix"};
  }
  return {SnapshotRejection::Truncated,
          std::string("expected more bits in ") + what + ", got the end of the stream"};
}

/// Reads one entity stream against its baseline (PROTOCOL.md Snapshots §4), a section per
/// method in stream order; each returns the refusal that stops it, if any.
class StreamReader {
 public:
  /// `kept`, `added`, `removed`: the decoder's buffers, whatever they held.
  StreamReader(const QuantizationSpec& spec, const SnapshotDecoderOptions& options,
               std::span<const QuantizedEntity> baseline, std::uint32_t baseline_age,
               const std::string& bytes, std::vector<QuantizedEntity>& kept,
               std::vector<QuantizedEntity>& added, std::vector<std::uint8_t>& removed)
      : options_(options),
        baseline_(baseline),
        widths_(spec),
        prediction_(layout::make_prediction(baseline_age, spec)),
        reader_(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(bytes.data()),
                                              bytes.size())),
        kept_(kept),
        added_(added),
        removed_(removed) {
    kept_.clear();
    added_.clear();
  }

  MaybeRefusal read_removals();
  MaybeRefusal read_additions();
  MaybeRefusal read_changes();
  MaybeRefusal check_end() const;
  /// The kept entities (changed) and the additions merged by id into `view` (without additions,
  /// the kept entities are swapped in).
  MaybeRefusal merge(std::vector<QuantizedEntity>& view);

 private:
  /// Follows ascending indices written as gaps: first gap, then previous + 1 + gap.
  static std::uint64_t next_index(std::uint64_t previous, std::uint64_t gap, bool first) {
    return first ? gap : previous + 1 + gap;
  }

  const SnapshotDecoderOptions& options_;
  std::span<const QuantizedEntity> baseline_;
  layout::FieldWidths widths_;
  layout::Prediction prediction_;
  BitReader reader_;
  std::vector<QuantizedEntity>& kept_;   ///< the baseline without the removals
  std::vector<QuantizedEntity>& added_;  ///< ids ascending
  std::vector<std::uint8_t>& removed_;   ///< by baseline index
};

MaybeRefusal StreamReader::read_removals() {
  const std::uint64_t count = reader_.read_exp_golomb(0);
  if (reader_.failed()) return reader_refusal(reader_, "the removal count");
  if (count > baseline_.size()) {
    return Refusal{SnapshotRejection::RemovedOutOfRange,
                   "expected at most " + std::to_string(baseline_.size()) +
                       " removals (the baseline's entities), got " + std::to_string(count)};
  }
  if (count == 0) {  // the common case: the baseline as it is
    kept_.assign(baseline_.begin(), baseline_.end());
    return std::nullopt;
  }
  removed_.assign(baseline_.size(), 0);
  const int order = static_cast<int>(reader_.read_bits(layout::kOrderBits));
  std::uint64_t index = 0;
  for (std::uint64_t k = 0; k < count; ++k) {
    const std::uint64_t gap = layout::read_code(reader_, order);
    if (reader_.failed()) return reader_refusal(reader_, "a removal");
    index = next_index(index, gap, k == 0);
    if (index >= baseline_.size()) {
      return Refusal{SnapshotRejection::RemovedOutOfRange, "expected a removal index below " +
                                                               std::to_string(baseline_.size()) +
                                                               ", got " + std::to_string(index)};
    }
    removed_[index] = 1;
  }
  kept_.reserve(baseline_.size() - count);
  for (std::size_t k = 0; k < baseline_.size(); ++k) {
    if (!removed_[k]) kept_.push_back(baseline_[k]);
  }
  return std::nullopt;
}

MaybeRefusal StreamReader::read_additions() {
  const std::uint64_t count = reader_.read_exp_golomb(0);
  if (reader_.failed()) return reader_refusal(reader_, "the addition count");
  if (kept_.size() + count > options_.max_entities) {
    return Refusal{SnapshotRejection::TooManyEntities,
                   "expected at most " + std::to_string(options_.max_entities) + " entities, got " +
                       std::to_string(kept_.size() + count)};
  }
  if (count == 0) return std::nullopt;
  if (count > reader_.bits_left()) return reader_refusal(reader_, "the additions");
  added_.resize(count);
  const int order = static_cast<int>(reader_.read_bits(layout::kOrderBits));
  std::uint64_t id = 0;
  for (std::uint64_t k = 0; k < count; ++k) {
    const std::uint64_t gap = layout::read_code(reader_, order);
    if (reader_.failed()) return reader_refusal(reader_, "an addition's id");
    id = next_index(id, gap, k == 0);
    if (id > 0xFFFFFFFFu) {
      return Refusal{SnapshotRejection::IdOutOfOrder,
                     "expected a new entity id below 2^32, got " + std::to_string(id)};
    }
    added_[k].id = static_cast<std::uint32_t>(id);
    const bool in_range = layout::read_absolute(reader_, widths_, added_[k]);
    if (reader_.failed()) return reader_refusal(reader_, "a new entity's state");
    if (!in_range) {
      return Refusal{SnapshotRejection::ValueOutOfRange,
                     "expected new entity " + std::to_string(id) +
                         " within the spec's ranges, got a value outside"};
    }
  }
  return std::nullopt;
}

MaybeRefusal StreamReader::read_changes() {
  const std::uint64_t count = reader_.read_exp_golomb(0);
  if (reader_.failed()) return reader_refusal(reader_, "the change count");
  if (count > kept_.size()) {
    return Refusal{SnapshotRejection::ChangedOutOfRange,
                   "expected at most " + std::to_string(kept_.size()) +
                       " changes (the kept entities), got " + std::to_string(count)};
  }
  if (count == 0) return std::nullopt;
  layout::DeltaOrders orders;
  auto read_order = [this] { return static_cast<int>(reader_.read_bits(layout::kOrderBits)); };
  orders.gap = read_order();
  for (int& order : orders.velocity) order = read_order();
  for (int& order : orders.position) order = read_order();
  orders.orientation = read_order();
  std::uint64_t index = 0;
  std::uint8_t previous_mask = layout::kInitialFieldMask;
  for (std::uint64_t k = 0; k < count; ++k) {
    const std::uint64_t gap = layout::read_code(reader_, orders.gap);
    if (reader_.failed()) return reader_refusal(reader_, "a change's gap");
    index = next_index(index, gap, k == 0);
    if (index >= kept_.size()) {
      return Refusal{SnapshotRejection::ChangedOutOfRange, "expected a change index below " +
                                                               std::to_string(kept_.size()) +
                                                               ", got " + std::to_string(index)};
    }
    QuantizedEntity& entity = kept_[index];
    const layout::DeltaStatus status =
        layout::read_delta(reader_, orders, widths_, prediction_, previous_mask, entity);
    if (reader_.failed()) return reader_refusal(reader_, "a change");
    if (status == layout::DeltaStatus::EmptyChange) {
      return Refusal{SnapshotRejection::EmptyChange, "expected a change to entity " +
                                                         std::to_string(entity.id) +
                                                         ", got its baseline state again"};
    }
    if (status == layout::DeltaStatus::OutOfRange) {
      return Refusal{SnapshotRejection::ValueOutOfRange,
                     "expected entity " + std::to_string(entity.id) +
                         " within the spec's ranges after its delta, got a value outside"};
    }
  }
  return std::nullopt;
}

MaybeRefusal StreamReader::check_end() const {
  if (reader_.only_padding_left()) return std::nullopt;
  return Refusal{SnapshotRejection::TrailingBits,
                 "expected only zero padding after the last change, got " +
                     std::to_string(reader_.bits_left()) + " more bits"};
}

MaybeRefusal StreamReader::merge(std::vector<QuantizedEntity>& view) {
  if (added_.empty()) {
    view.swap(kept_);
    return std::nullopt;
  }
  view.clear();
  view.reserve(kept_.size() + added_.size());
  std::size_t k = 0, a = 0;
  while (k < kept_.size() || a < added_.size()) {
    if (a == added_.size() || (k < kept_.size() && kept_[k].id < added_[a].id)) {
      view.push_back(kept_[k++]);
    } else if (k == kept_.size() || added_[a].id < kept_[k].id) {
      view.push_back(added_[a++]);
    } else {
      return Refusal{SnapshotRejection::IdOutOfOrder,
                     "expected new entity ids not already held, got " +
                         std::to_string(added_[a].id) + " again"};
    }
  }
  return std::nullopt;
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

  // The header: size, tick order, baseline.
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

  // The stream, section by section, into a new view.
  StreamReader stream(spec_, options_, baseline, in.baseline_age(), bytes, kept_, added_, removed_);
  MaybeRefusal refusal = stream.read_removals();
  if (!refusal) refusal = stream.read_additions();
  if (!refusal) refusal = stream.read_changes();
  if (!refusal) refusal = stream.check_end();
  if (!refusal) refusal = stream.merge(view_);
  if (refusal) return refuse(std::move(*refusal));

  // The baseline is read; its slot may now take the new view.
  Decoded& entry = ring_[in.tick() % ring_.size()];
  entry.valid = true;
  entry.tick = in.tick();
  entry.view.swap(view_);
  has_newest_ = true;
  newest_tick_ = in.tick();
  ++accepted_;
  result.ok = true;
  result.entities = entry.view;
  return result;
}

}  // namespace ricochet::proto
