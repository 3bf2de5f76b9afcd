/// The results outbox file format (results_outbox_format.h).

#include "results_outbox_format.h"

#include <algorithm>
#include <bit>
#include <string_view>

#include "../match/recording_format.h"  // crc32
#include "ricochet/db/matches.h"

namespace ricochet::server {

namespace {

/// One player's bytes in the payload.
constexpr std::size_t kPlayerBytes = 8 + 4 * 6 + 8 * 3;

class Writer {
 public:
  explicit Writer(std::vector<std::uint8_t>& out) : out_(out) {}
  void u8(std::uint8_t v) { out_.push_back(v); }
  void u16(std::uint16_t v) { le(v, 2); }
  void u32(std::uint32_t v) { le(v, 4); }
  void i32(std::int32_t v) { le(static_cast<std::uint32_t>(v), 4); }
  void i64(std::int64_t v) { le(static_cast<std::uint64_t>(v), 8); }
  void f64(double v) { le(std::bit_cast<std::uint64_t>(v), 8); }
  void bytes(std::string_view s) { out_.insert(out_.end(), s.begin(), s.end()); }
  void short_text(std::string_view s) {
    u8(static_cast<std::uint8_t>(std::min<std::size_t>(s.size(), 255)));
    bytes(s.substr(0, 255));
  }

 private:
  void le(std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) out_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  std::vector<std::uint8_t>& out_;
};

/// Reads from the front of `bytes`; once a read runs past the end, every read gives 0 and
/// short() says what was being read.
class Reader {
 public:
  explicit Reader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}
  std::uint8_t u8(const char* what) { return static_cast<std::uint8_t>(le(1, what)); }
  std::uint16_t u16(const char* what) { return static_cast<std::uint16_t>(le(2, what)); }
  std::uint32_t u32(const char* what) { return static_cast<std::uint32_t>(le(4, what)); }
  std::int32_t i32(const char* what) { return static_cast<std::int32_t>(u32(what)); }
  std::int64_t i64(const char* what) { return static_cast<std::int64_t>(le(8, what)); }
  double f64(const char* what) { return std::bit_cast<double>(le(8, what)); }
  std::string text(std::size_t n, const char* what) {
    if (!take(n, what)) return {};
    return std::string(reinterpret_cast<const char*>(bytes_.data() + at_ - n), n);
  }
  std::size_t left() const { return bytes_.size() - at_; }
  std::size_t at() const { return at_; }
  /// Empty while every read fit; else "truncated: <what> at byte N".
  const std::string& short_read() const { return short_; }

 private:
  bool take(std::size_t n, const char* what) {
    if (!short_.empty()) return false;
    if (left() < n) {
      short_ = std::string("truncated: ") + what + " at byte " + std::to_string(at_) + " needs " +
               std::to_string(n) + " bytes, " + std::to_string(left()) + " left";
      return false;
    }
    at_ += n;
    return true;
  }
  std::uint64_t le(std::size_t n, const char* what) {
    if (!take(n, what)) return 0;
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < n; ++i) v |= std::uint64_t{bytes_[at_ - n + i]} << (8 * i);
    return v;
  }
  std::span<const std::uint8_t> bytes_;
  std::size_t at_ = 0;
  std::string short_;
};

DecodedOutbox refused(std::string problem) {
  DecodedOutbox out;
  out.problem = std::move(problem);
  return out;
}

}  // namespace

std::vector<std::uint8_t> encode_outbox_record(const OutboxRecord& kept) {
  const db::MatchRecord& r = kept.record;
  std::vector<std::uint8_t> payload;
  Writer p(payload);
  p.bytes(std::string_view(r.uuid).substr(0, db::kMatchUuidChars));
  p.u32(kept.match_id);
  p.i64(r.started_ms);
  p.i64(r.ended_ms);
  p.i32(r.tick_rate);
  p.u8(r.aborted ? 1 : 0);
  p.i32(r.team_scores.red);
  p.i32(r.team_scores.blue);
  p.short_text(r.map);
  p.short_text(r.mode);
  const std::size_t players = std::min(r.players.size(), kMaxOutboxPlayers);
  p.u16(static_cast<std::uint16_t>(players));
  for (std::size_t i = 0; i < players; ++i) {
    const db::PlayerResult& player = r.players[i];
    p.i64(player.account);
    for (const std::int32_t v :
         {player.team, player.kills, player.deaths, player.score, player.shots, player.hits})
      p.i32(v);
    p.f64(player.damage_dealt);
    p.f64(player.damage_taken);
    p.f64(player.seconds_played);
  }
  std::vector<std::uint8_t> file(kOutboxMagic.begin(), kOutboxMagic.end());
  file.reserve(kOutboxHeaderBytes + payload.size());
  Writer f(file);
  f.u16(kOutboxVersion);
  f.u32(static_cast<std::uint32_t>(payload.size()));
  f.u32(recording_format::crc32(payload));
  file.insert(file.end(), payload.begin(), payload.end());
  return file;
}

DecodedOutbox decode_outbox_record(std::span<const std::uint8_t> bytes) {
  if (bytes.size() > kMaxOutboxFileBytes)
    return refused("oversized: " + std::to_string(bytes.size()) + " bytes, at most " +
                   std::to_string(kMaxOutboxFileBytes));
  if (bytes.size() < kOutboxHeaderBytes)
    return refused("truncated: " + std::to_string(bytes.size()) + " bytes, a header is " +
                   std::to_string(kOutboxHeaderBytes));
  if (!std::equal(kOutboxMagic.begin(), kOutboxMagic.end(), bytes.begin()))
    return refused("not an outbox file: the first 8 bytes are not \"RCOUTBOX\"");
  Reader head(bytes.subspan(kOutboxMagic.size()));
  const std::uint16_t version = head.u16("version");
  const std::uint32_t length = head.u32("length");
  const std::uint32_t crc = head.u32("crc");
  if (version != kOutboxVersion)
    return refused("version " + std::to_string(version) + ", this build reads " +
                   std::to_string(kOutboxVersion));
  if (length > kMaxOutboxPayloadBytes)
    return refused("oversized: a payload of " + std::to_string(length) + " bytes, at most " +
                   std::to_string(kMaxOutboxPayloadBytes));
  const std::span<const std::uint8_t> payload = bytes.subspan(kOutboxHeaderBytes);
  if (payload.size() < length)
    return refused("truncated: the payload is " + std::to_string(length) + " bytes, " +
                   std::to_string(payload.size()) + " are there");
  if (payload.size() > length)
    return refused("trailing bytes: " + std::to_string(payload.size() - length) +
                   " after the payload");
  if (const std::uint32_t actual = recording_format::crc32(payload); actual != crc)
    return refused("CRC-32 mismatch: the header says " + std::to_string(crc) +
                   ", the payload has " + std::to_string(actual));

  Reader in(payload);
  DecodedOutbox out;
  db::MatchRecord& r = out.record.record;
  r.uuid = in.text(db::kMatchUuidChars, "uuid");
  out.record.match_id = in.u32("match id");
  r.started_ms = in.i64("started_ms");
  r.ended_ms = in.i64("ended_ms");
  r.tick_rate = in.i32("tick_rate");
  const std::uint8_t aborted = in.u8("aborted");
  r.team_scores.red = in.i32("red score");
  r.team_scores.blue = in.i32("blue score");
  r.map = in.text(in.u8("map length"), "map");
  r.mode = in.text(in.u8("mode length"), "mode");
  const std::uint16_t players = in.u16("player count");
  if (!in.short_read().empty()) return refused(in.short_read());
  if (!db::is_match_uuid(r.uuid)) return refused("the uuid is not 32 lowercase hex digits");
  if (aborted > 1) return refused("aborted must be 0 or 1, got " + std::to_string(aborted));
  if (players == 0 || players > kMaxOutboxPlayers)
    return refused("player count must be 1.." + std::to_string(kMaxOutboxPlayers) + ", got " +
                   std::to_string(players));
  if (in.left() != std::size_t{players} * kPlayerBytes)
    return refused("the payload holds " + std::to_string(in.left()) + " bytes of players, " +
                   std::to_string(players) + " players are " +
                   std::to_string(std::size_t{players} * kPlayerBytes));
  r.aborted = aborted == 1;
  for (std::uint16_t i = 0; i < players; ++i) {
    db::PlayerResult& p = r.players.emplace_back();
    p.account = in.i64("account");
    p.team = in.i32("team");
    p.kills = in.i32("kills");
    p.deaths = in.i32("deaths");
    p.score = in.i32("score");
    p.shots = in.i32("shots");
    p.hits = in.i32("hits");
    p.damage_dealt = in.f64("damage_dealt");
    p.damage_taken = in.f64("damage_taken");
    p.seconds_played = in.f64("seconds_played");
  }
  out.ok = true;
  return out;
}

}  // namespace ricochet::server
