#include "match_registry.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <iterator>
#include <optional>
#include <random>
#include <stdexcept>
#include <utility>

#include "ricochet/proto/chat_text.h"
#include "ricochet/proto/connect_token.h"
#include "ricochet/server/collision_world.h"
#include "steady_time.h"

namespace ricochet::server {

namespace {

DirectoryError error(DirectoryErrorCode code, std::string message) {
  return DirectoryError{code, std::move(message)};
}

/// A match seed from the system's entropy (rules.seed 0).
std::uint64_t random_seed() {
  std::random_device device;
  return (static_cast<std::uint64_t>(device()) << 32) | device();
}

constexpr double kCreateBurst = 10;        ///< match creations at once, the whole server
constexpr double kAccountCreateBurst = 1;  ///< by one account
/// How long a reservation is safe from giving way to a newer join at the bound: a client
/// connects its game channel within a round trip or two of its join reply.
constexpr proto::TimeUs kReservationGrace = proto::kMicrosPerSecond;

std::string account_key(std::uint64_t account) {
  return "account " + std::to_string(account);
}

/// Why a created match's name is refused (the chat text rule, 32 bytes at most), or nothing.
std::optional<std::string> refuse_match_name(const std::string& name) {
  constexpr std::size_t kMaxMatchNameBytes = 32;
  if (name.empty() || name.size() > kMaxMatchNameBytes) {
    return "name must be 1.." + std::to_string(kMaxMatchNameBytes) + " bytes, got " +
           std::to_string(name.size());
  }
  // The chat rule's message speaks of chat text: the field is named before it.
  if (const auto refusal = proto::check_chat_text(name)) return "name: " + refusal->message;
  return std::nullopt;
}

}  // namespace

const char* name(SeatRefusal refusal) {
  switch (refusal) {
    case SeatRefusal::AddressSeats:
      return "address_seats";
    case SeatRefusal::ReservedSeats:
      return "reserved_seats";
    case SeatRefusal::CreatedMatches:
      return "created_matches";
    case SeatRefusal::AccountMatches:
      return "account_matches";
    case SeatRefusal::CreateRate:
      return "create_rate";
    case SeatRefusal::AccountCreateRate:
      return "account_create_rate";
  }
  return "unknown";
}

MatchRegistry::MatchRegistry(boost::asio::io_context& io, MatchRegistryConfig config,
                             std::vector<Map> maps, GameChannel& channel, MatchEndedHandler ended)
    : io_(io),
      config_(std::move(config)),
      maps_(std::move(maps)),
      channel_(channel),
      ended_(std::move(ended)),
      creates_(config_.limits.creates_per_minute / 60.0, kCreateBurst, config_.clock()) {
  if (maps_.empty()) throw std::invalid_argument("MatchRegistry needs at least one map");
}

MatchRegistry::~MatchRegistry() = default;

DirectoryResult<MatchSummary> MatchRegistry::open(const std::string& name, int max_players,
                                                  std::size_t map, std::uint64_t creator) {
  MatchConfig match_config = config_.match_defaults;
  {
    const std::lock_guard lock(mutex_);
    if (auto refused = refuse_open(creator, config_.clock())) return *refused;
    match_config.id = next_match_id_++;  // an id is never reused, even when the build fails
  }
  match_config.name = name;
  match_config.max_players = max_players;
  if (match_config.rules.seed == 0) match_config.rules.seed = random_seed();
  map %= maps_.size();
  // The world is built outside the lock: routing and the control channel never wait for it.
  // The match runs on its host's clock, the steady one (match_host.cpp), not the seats' clock.
  auto created = Match::create(match_config, maps_[map], steady_now_us(), [] {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
  });
  if (auto* problem = std::get_if<std::string>(&created)) {
    return error(DirectoryErrorCode::InvalidRequest, *problem);
  }
  const std::uint32_t id = match_config.id;
  auto host = std::make_shared<MatchHost>(
      io_, std::move(std::get<Match>(created)), channel_,
      [this](std::uint64_t account, std::uint32_t match_id, std::uint64_t seat) {
        release(account, match_id, seat);
      },
      [this, id](EndedMatch ended) { match_ended(id, std::move(ended)); }, config_.recordings);
  std::shared_ptr<const wire::CollisionWorld> world =
      collision_world(maps_[map], match_config.movement);
  if (!world) {
    spdlog::warn(
        "map {}: its collision world is over the {} bytes a join reply carries; clients of "
        "its matches cannot predict (simplify the meshes)",
        maps_[map].name, kMaxCollisionWorldBytes);
  }
  const std::lock_guard lock(mutex_);
  const proto::TimeUs now = config_.clock();
  // Checked again: the registry may have closed or filled while the world was built.
  if (auto refused = refuse_open(creator, now)) return *refused;
  host->start();
  hosts_.emplace(
      id, Hosted{host, map, std::move(world), weapon_specs(match_config.weapons), creator, now});
  spdlog::info("match {} '{}' open: {} on map {} for {} players, seed {}", id, name,
               server::name(match_config.rules.mode), host->map_name(), max_players,
               match_config.rules.seed);
  return summary(*host, now);
}

void MatchRegistry::set_udp_port(std::uint16_t port) {
  const std::lock_guard lock(mutex_);
  config_.udp_port = port;
}

void MatchRegistry::close() {
  const std::lock_guard lock(mutex_);
  closed_ = true;
}

std::vector<std::shared_ptr<MatchHost>> MatchRegistry::hosts() const {
  const std::lock_guard lock(mutex_);
  std::vector<std::shared_ptr<MatchHost>> out;
  for (const auto& [id, hosted] : hosts_) out.push_back(hosted.host);
  return out;
}

std::size_t MatchRegistry::seats() const {
  const std::lock_guard lock(mutex_);
  const proto::TimeUs now = config_.clock();
  return static_cast<std::size_t>(std::count_if(
      seats_.begin(), seats_.end(), [now](const auto& seat) { return holds(seat.second, now); }));
}

std::vector<MatchSummary> MatchRegistry::list() const {
  const std::lock_guard lock(mutex_);
  std::vector<MatchSummary> out;
  const proto::TimeUs now = config_.clock();
  for (const auto& [id, hosted] : hosts_) out.push_back(summary(*hosted.host, now));
  return out;
}

void MatchRegistry::set_held_seats(boost::unordered_flat_map<std::uint32_t, int> held) {
  const std::lock_guard lock(mutex_);
  held_by_tickets_ = std::move(held);
}

void MatchRegistry::close_empty_matches() {
  std::vector<std::shared_ptr<MatchHost>> empty;
  {
    const std::lock_guard lock(mutex_);
    empty = take_empty_matches(config_.clock());
  }
  end_empty_matches(std::move(empty));
}

std::uint64_t MatchRegistry::refused(SeatRefusal refusal) const {
  return refused_[static_cast<std::size_t>(refusal)].load(std::memory_order_relaxed);
}

DirectoryResult<MatchSummary> MatchRegistry::create(const CreateMatchRequest& request) {
  if (const auto refusal = refuse_match_name(request.name)) {
    return error(DirectoryErrorCode::InvalidRequest, *refusal);
  }
  if (request.max_players < 1 || request.max_players > 64) {
    return error(DirectoryErrorCode::InvalidRequest,
                 "max_players must be 1..64, got " + std::to_string(request.max_players));
  }
  std::size_t map = 0;  // empty: the rotation's first
  if (!request.map.empty()) {
    const auto named = std::find_if(maps_.begin(), maps_.end(),
                                    [&](const Map& loaded) { return loaded.name == request.map; });
    if (named == maps_.end()) {
      std::string known;
      for (const Map& loaded : maps_) known += (known.empty() ? "'" : ", '") + loaded.name + "'";
      return error(
          DirectoryErrorCode::InvalidRequest,
          "map must be one of the loaded maps (" + known + ") or empty, got '" + request.map + "'");
    }
    map = static_cast<std::size_t>(named - maps_.begin());
  }
  std::vector<std::shared_ptr<MatchHost>> empty;
  std::optional<DirectoryError> refused;
  {
    const std::lock_guard lock(mutex_);
    const proto::TimeUs now = config_.clock();
    empty = take_empty_matches(now);
    // The counts first (they spend nothing), then the server's and the account's rates.
    refused = refuse_open(request.creator, now);
    if (!refused && !creates_.take(now)) {
      refused = refuse(SeatRefusal::CreateRate, "server", DirectoryErrorCode::CreateRateLimited,
                       "this server creates at most " +
                           std::to_string(config_.limits.creates_per_minute) +
                           " matches a minute; try again shortly",
                       now);
    }
    if (!refused && request.creator != kPlacementCreator) {
      auto bucket = account_creates_.try_emplace(
          request.creator, config_.limits.creates_per_account_per_minute / 60.0,
          kAccountCreateBurst, now);
      if (!bucket.first->second.take(now)) {
        refused = refuse(SeatRefusal::AccountCreateRate, account_key(request.creator),
                         DirectoryErrorCode::CreateRateLimited,
                         "an account creates at most " +
                             std::to_string(config_.limits.creates_per_account_per_minute) +
                             " matches a minute; try again shortly",
                         now);
      }
      for (auto it = account_creates_.begin(); it != account_creates_.end();) {
        it = it->second.full(now) ? account_creates_.erase(it) : std::next(it);
      }
    }
  }
  end_empty_matches(std::move(empty));
  if (refused) return *refused;
  return open(request.name, request.max_players, map, request.creator);
}

DirectoryResult<JoinGrant> MatchRegistry::join(std::uint64_t account, const std::string& username,
                                               std::uint32_t match_id, const JoinOrigin& origin) {
  std::vector<std::shared_ptr<MatchHost>> empty;
  DirectoryResult<JoinGrant> result = DirectoryError{DirectoryErrorCode::ShuttingDown, ""};
  {
    const std::lock_guard lock(mutex_);
    const proto::TimeUs now = config_.clock();
    expire_reservations(now);
    empty = take_empty_matches(now);
    result = join_locked(account, username, match_id, origin, now);
  }
  end_empty_matches(std::move(empty));
  return result;
}

DirectoryResult<JoinGrant> MatchRegistry::join_locked(std::uint64_t account,
                                                      const std::string& username,
                                                      std::uint32_t match_id,
                                                      const JoinOrigin& origin, proto::TimeUs now) {
  if (closed_) return error(DirectoryErrorCode::ShuttingDown, "the server is shutting down");
  const auto host = hosts_.find(match_id);
  if (host == hosts_.end()) {
    return error(DirectoryErrorCode::MatchNotFound, "no match " + std::to_string(match_id));
  }
  auto seat = seats_.find(account);
  if (seat != seats_.end() && seat->second.match_id != match_id) {
    return error(DirectoryErrorCode::AlreadyInMatch,
                 "already in match " + std::to_string(seat->second.match_id) + "; leave it first");
  }
  if (seat == seats_.end()) {
    if (auto refused = refuse_seat(match_id, host->second.host->max_players(), origin, now)) {
      return *refused;
    }
    seat =
        seats_.emplace(account, Seat{match_id, username, false, false, 0, 0, origin.host, 0, now})
            .first;
  } else if (seat->second.session != origin.session) {
    // One session plays the account: the newest join's. The older session's game connection
    // goes (the player keeps its place within the reconnect grace and comes back with this
    // join's token).
    spdlog::info("match {}: account {} is played from control session {} now, not {}", match_id,
                 account, origin.session, seat->second.session);
    if (seat->second.taken) channel_.kick(account, proto::DisconnectReason::Kicked);
  }
  seat->second.session = origin.session;
  seat->second.session_token = origin.session_token;
  seat->second.host = origin.host;
  JoinGrant grant;
  grant.match_id = match_id;
  grant.udp_port = config_.udp_port;
  grant.quantization = host->second.host->quantization();
  grant.tick_rate_hz = host->second.host->tick_rate_hz();
  grant.snapshot_rate_hz = host->second.host->snapshot_rate_hz();
  grant.world = host->second.world;
  grant.weapons = host->second.weapons;
  grant.token = token_for(account, match_id, now);
  // A taken seat stays taken (a reconnect); a reservation lives as long as its newest token.
  seat->second.reserved_until =
      grant.token.expires_at +
      static_cast<proto::TimeUs>(grant.token.timeout_s) * proto::kMicrosPerSecond;
  return grant;
}

std::optional<std::uint32_t> MatchRegistry::rejoin(std::uint64_t account,
                                                   const JoinOrigin& origin) {
  const std::lock_guard lock(mutex_);
  expire_reservations(config_.clock());
  const auto seat = seats_.find(account);
  // Only the sign-in that joined gets the seat back: another device's token does not take over
  // a game connection it does not play (it may join, which kicks that connection instead).
  if (seat == seats_.end() || origin.session_token.empty() ||
      seat->second.session_token != origin.session_token) {
    return std::nullopt;
  }
  spdlog::info("match {}: account {} resumed on control session {} (was {})", seat->second.match_id,
               account, origin.session, seat->second.session);
  seat->second.session = origin.session;
  seat->second.host = origin.host;
  return seat->second.match_id;
}

DirectoryResult<Done> MatchRegistry::leave(std::uint64_t account, std::uint64_t session) {
  std::shared_ptr<MatchHost> host;
  {
    const std::lock_guard lock(mutex_);
    const auto seat = seats_.find(account);
    if (seat == seats_.end()) return error(DirectoryErrorCode::NotInMatch, "not in a match");
    if (seat->second.session != session) {
      return error(DirectoryErrorCode::NotInMatch,
                   "the account is played from another control connection now");
    }
    host = hosts_.at(seat->second.match_id).host;
    seats_.erase(seat);
    issued_tokens_.erase(account);
  }
  // Closed now, not from the match's strand: a connection made after a quick rejoin must not be
  // the one a late kick finds.
  channel_.kick(account, proto::DisconnectReason::Left);
  host->leave(account);
  return Done{};
}

bool MatchRegistry::remove(std::uint64_t account, proto::DisconnectReason reason) {
  std::shared_ptr<MatchHost> host;
  {
    const std::lock_guard lock(mutex_);
    issued_tokens_.erase(account);
    const auto seat = seats_.find(account);
    if (seat == seats_.end()) return false;
    host = hosts_.at(seat->second.match_id).host;
    seats_.erase(seat);
  }
  channel_.kick(account, reason);  // now, as leave() does
  host->leave(account);
  return true;
}

DirectoryResult<Done> MatchRegistry::chat(std::uint64_t account, std::uint64_t session,
                                          const std::string& text) {
  std::shared_ptr<MatchHost> host;
  {
    const std::lock_guard lock(mutex_);
    const auto seat = seats_.find(account);
    if (seat == seats_.end()) return error(DirectoryErrorCode::NotInMatch, "not in a match");
    if (seat->second.session != session) {
      return error(DirectoryErrorCode::NotInMatch,
                   "the account is played from another control connection now; chat from that one");
    }
    if (!seat->second.connected) {
      return error(DirectoryErrorCode::NotInMatch,
                   "your game connection is not up, so the match would drop the line; chat once "
                   "it is connected");
    }
    host = hosts_.at(seat->second.match_id).host;
  }
  const auto over = config_.chat_limiter
                        ? config_.chat_limiter->take(account, host->id(), config_.clock())
                        : std::nullopt;
  if (over) return error(DirectoryErrorCode::RateLimited, config_.chat_limiter->explain(*over));
  host->chat(account, text);
  return Done{};
}

void MatchRegistry::connected(std::uint64_t account, std::uint32_t match_id) {
  std::shared_ptr<MatchHost> host;
  std::string username;
  std::uint64_t generation = 0;
  {
    const std::lock_guard lock(mutex_);
    issued_tokens_.erase(account);  // used: the next join needs a new token
    const auto seat = seats_.find(account);
    if (!closed_ && seat != seats_.end() && seat->second.match_id == match_id) {
      seat->second.taken = true;
      seat->second.connected = true;
      seat->second.generation = next_generation_++;
      generation = seat->second.generation;
      host = hosts_.at(match_id).host;
      username = seat->second.username;
    }
  }
  if (!host) {
    // The token was good, but the account left (or was never seated here) since it was issued,
    // or the server is stopping.
    spdlog::debug("game channel: account {} connected to match {} without a seat; kicked", account,
                  match_id);
    channel_.kick(account, proto::DisconnectReason::Kicked);
    return;
  }
  host->connect(account, std::move(username), generation);
}

void MatchRegistry::disconnected(std::uint64_t account, proto::DisconnectReason reason) {
  {
    const std::lock_guard lock(mutex_);
    // The channel reports only the end of the account's newest connection.
    if (const auto seat = seats_.find(account); seat != seats_.end()) {
      seat->second.connected = false;
    }
  }
  if (const auto host = host_of(account)) {
    spdlog::debug("game channel: account {} gone ({})", account, proto::name(reason));
    host->disconnect(account);
  }
}

void MatchRegistry::payloads(std::vector<GamePayload> batch) {
  // Sorted by match under one lock, then one post per match (a wake-up mostly brings the
  // inputs of a few matches: the linear search is over those).
  std::vector<std::pair<std::shared_ptr<MatchHost>, std::vector<GamePayload>>> by_host;
  {
    const std::lock_guard lock(mutex_);
    for (GamePayload& payload : batch) {
      const auto seat = seats_.find(payload.account);
      if (seat == seats_.end()) continue;
      const std::shared_ptr<MatchHost>& host = hosts_.at(seat->second.match_id).host;
      auto share = std::find_if(by_host.begin(), by_host.end(),
                                [&](const auto& entry) { return entry.first == host; });
      if (share == by_host.end()) share = by_host.insert(by_host.end(), {host, {}});
      share->second.push_back(std::move(payload));
    }
  }
  for (auto& [host, payloads] : by_host) host->receive(std::move(payloads));
}

void MatchRegistry::reliable(std::uint64_t account, std::vector<std::uint8_t> bytes) {
  // No client-to-server reliable message is defined (chat goes up the control channel).
  unexpected_reliable_.fetch_add(1, std::memory_order_relaxed);
  spdlog::debug("game channel: account {} sent a reliable message of {} bytes; none is defined",
                account, bytes.size());
}

proto::TokenGrant MatchRegistry::token_for(std::uint64_t account, std::uint32_t match_id,
                                           proto::TimeUs now) {
  boost::unordered::erase_if(issued_tokens_, [&](const auto& entry) {
    return entry.second.issued_at + config_.token_reuse_us <= now ||
           entry.second.grant.expires_at <= now;
  });
  if (const auto issued = issued_tokens_.find(account);
      issued != issued_tokens_.end() && issued->second.match_id == match_id) {
    return issued->second.grant;
  }
  proto::TokenGrant grant =
      proto::issue_connect_token(config_.token_key, proto::kProtocolId, account, match_id, now,
                                 config_.token_lifetime_us, config_.token_timeout_s);
  if (config_.token_reuse_us > 0) issued_tokens_[account] = {match_id, grant, now};
  return grant;
}

void MatchRegistry::expire_reservations(proto::TimeUs now) {
  boost::unordered::erase_if(seats_,
                             [now](const auto& entry) { return !holds(entry.second, now); });
}

std::optional<DirectoryError> MatchRegistry::refuse_open(std::uint64_t creator, proto::TimeUs now) {
  if (closed_) return error(DirectoryErrorCode::ShuttingDown, "the server is shutting down");
  if (static_cast<int>(hosts_.size()) >= config_.max_matches) {
    return error(DirectoryErrorCode::TooManyMatches,
                 "this server hosts at most " + std::to_string(config_.max_matches) + " matches");
  }
  if (creator == 0) return std::nullopt;
  int created = 0;
  int by_creator = 0;
  for (const auto& [id, hosted] : hosts_) {
    created += hosted.creator != 0 ? 1 : 0;
    by_creator += hosted.creator == creator ? 1 : 0;
  }
  const SeatLimits& limits = config_.limits;
  if (creator != kPlacementCreator && by_creator >= limits.created_matches_per_account) {
    return refuse(
        SeatRefusal::AccountMatches, account_key(creator), DirectoryErrorCode::TooManyMatches,
        "an account may have " + std::to_string(limits.created_matches_per_account) +
            " created matches open at once; an empty one closes after " +
            std::to_string(limits.empty_match_close_after_us / proto::kMicrosPerSecond) + " s",
        now);
  }
  if (created >= limits.created_matches) {
    return refuse(SeatRefusal::CreatedMatches, "server", DirectoryErrorCode::TooManyMatches,
                  "this server hosts at most " + std::to_string(limits.created_matches) +
                      " created matches; join one of them",
                  now);
  }
  return std::nullopt;
}

std::optional<DirectoryError> MatchRegistry::refuse_seat(std::uint32_t match_id, int max_players,
                                                         const JoinOrigin& origin,
                                                         proto::TimeUs now) {
  int held = 0;
  int reserved = 0;
  int from_address = 0;
  for (const auto& [account, seat] : seats_) {
    if (!holds(seat, now)) continue;
    if (seat.match_id == match_id) {
      ++held;
      reserved += seat.taken ? 0 : 1;
    }
    from_address += seat.host == origin.host ? 1 : 0;
  }
  const SeatLimits& limits = config_.limits;
  if (held >= max_players) {
    return error(DirectoryErrorCode::MatchFull, "match " + std::to_string(match_id) + " has all " +
                                                    std::to_string(max_players) + " seats taken");
  }
  if (!origin.placed) {
    const auto tickets = held_by_tickets_.find(match_id);
    const int for_tickets = tickets == held_by_tickets_.end() ? 0 : tickets->second;
    if (held + for_tickets >= max_players) {
      return error(DirectoryErrorCode::MatchFull,
                   "match " + std::to_string(match_id) + " has " + std::to_string(held) +
                       " seats taken and " + std::to_string(for_tickets) +
                       " held for players placed here, of " + std::to_string(max_players));
    }
  }
  if (from_address >= limits.seats_per_address) {
    return refuse(SeatRefusal::AddressSeats, origin.host.to_string(),
                  DirectoryErrorCode::AddressSeatLimit,
                  "your address holds " + std::to_string(from_address) +
                      " seats, the most one address may; leave a match first",
                  now);
  }
  // Never more than half the match's seats, so that reservations alone cannot fill it. At the
  // bound, the oldest reservation still unused after kReservationGrace gives way to this join.
  if (reserved >= std::min(limits.reserved_seats_per_match, std::max(1, max_players / 2))) {
    auto oldest = seats_.end();
    for (auto it = seats_.begin(); it != seats_.end(); ++it) {
      const Seat& seat = it->second;
      if (seat.match_id != match_id || seat.taken || !holds(seat, now)) continue;
      if (oldest == seats_.end() || seat.reserved_at < oldest->second.reserved_at) oldest = it;
    }
    const bool stale =
        oldest != seats_.end() && now - oldest->second.reserved_at >= kReservationGrace;
    const std::string key = stale ? oldest->second.host.to_string() : origin.host.to_string();
    DirectoryError refused =
        refuse(SeatRefusal::ReservedSeats, key, DirectoryErrorCode::MatchFull,
               "match " + std::to_string(match_id) + " has " + std::to_string(reserved) +
                   " players still connecting, the most it waits for at once; try again in a "
                   "second",
               now);
    if (!stale) return refused;
    spdlog::debug("match {}: account {}'s seat, reserved {} ms ago and unused, given up", match_id,
                  oldest->first, (now - oldest->second.reserved_at) / proto::kMicrosPerMilli);
    seats_.erase(oldest);
  }
  return std::nullopt;
}

DirectoryError MatchRegistry::refuse(SeatRefusal refusal, const std::string& key,
                                     DirectoryErrorCode code, std::string message,
                                     proto::TimeUs now) {
  refused_[static_cast<std::size_t>(refusal)].fetch_add(1, std::memory_order_relaxed);
  if (config_.episodes) config_.episodes->refuse(name(refusal), key, message, now);
  return error(code, std::move(message));
}

std::vector<std::shared_ptr<MatchHost>> MatchRegistry::take_empty_matches(proto::TimeUs now) {
  std::vector<std::shared_ptr<MatchHost>> empty;
  if (closed_) return empty;  // the stop ends every match itself
  for (auto it = hosts_.begin(); it != hosts_.end();) {
    Hosted& hosted = it->second;
    if (hosted.creator == 0 || seats_in(it->first, now) > 0) {
      hosted.last_seated_at = now;
      ++it;
    } else if (now - hosted.last_seated_at >= config_.limits.empty_match_close_after_us) {
      spdlog::info(
          "match {} '{}' closed: created by {}, empty for {} s", it->first, hosted.host->name(),
          hosted.creator == kPlacementCreator ? std::string("placement")
                                              : "account " + std::to_string(hosted.creator),
          (now - hosted.last_seated_at) / proto::kMicrosPerSecond);
      empty.push_back(hosted.host);
      it = hosts_.erase(it);
    } else {
      ++it;
    }
  }
  return empty;
}

void MatchRegistry::end_empty_matches(std::vector<std::shared_ptr<MatchHost>> hosts) {
  for (const auto& host : hosts) {
    empty_matches_closed_.fetch_add(1, std::memory_order_relaxed);
    host->end([this](EndedMatch ended) { ended_(std::move(ended)); });
  }
}

bool MatchRegistry::holds(const Seat& seat, proto::TimeUs now) {
  return seat.taken || seat.reserved_until > now;
}

int MatchRegistry::seats_in(std::uint32_t match_id, proto::TimeUs now) const {
  return static_cast<int>(
      std::count_if(seats_.begin(), seats_.end(), [match_id, now](const auto& seat) {
        return seat.second.match_id == match_id && holds(seat.second, now);
      }));
}

MatchSummary MatchRegistry::summary(const MatchHost& host, proto::TimeUs now) const {
  MatchSummary out;
  out.id = host.id();
  out.name = host.name();
  out.mode = server::name(host.mode());
  out.map = host.map_name();
  out.players = seats_in(host.id(), now);
  out.max_players = host.max_players();
  return out;
}

std::shared_ptr<MatchHost> MatchRegistry::host_of(std::uint64_t account) const {
  const std::lock_guard lock(mutex_);
  const auto seat = seats_.find(account);
  if (seat == seats_.end()) return nullptr;
  return hosts_.at(seat->second.match_id).host;
}

void MatchRegistry::match_ended(std::uint32_t match_id, EndedMatch ended) {
  std::string name;
  int max_players = 0;
  std::size_t map = 0;
  std::uint64_t creator = 0;
  std::vector<std::uint64_t> seated;
  {
    const std::lock_guard lock(mutex_);
    const auto found = hosts_.find(match_id);
    if (found != hosts_.end()) {
      name = found->second.host->name();
      max_players = found->second.host->max_players();
      map = found->second.map;
      creator = found->second.creator;
      hosts_.erase(found);
    }
    boost::unordered::erase_if(seats_, [&](const auto& seat) {
      if (seat.second.match_id != match_id) return false;
      seated.push_back(seat.first);
      return true;
    });
  }
  // Posted to the channel after the MatchEnded the host just sent, which goes out first; and
  // before the seat could be taken elsewhere, so no later connection of the account is hit.
  for (const std::uint64_t account : seated)
    channel_.kick(account, proto::DisconnectReason::Kicked);
  if (!name.empty()) {
    const auto next = open(name, max_players, next_in_rotation(map), creator);
    if (const auto* problem = std::get_if<DirectoryError>(&next)) {
      spdlog::info("match {} '{}' is not followed by another: {}", match_id, name,
                   problem->message);
    } else {
      spdlog::info("match {} '{}' is followed by match {} on map {}", match_id, name,
                   std::get<MatchSummary>(next).id, std::get<MatchSummary>(next).map);
    }
  }
  ended_(std::move(ended));
}

void MatchRegistry::release(std::uint64_t account, std::uint32_t match_id,
                            std::uint64_t generation) {
  const std::lock_guard lock(mutex_);
  const auto seat = seats_.find(account);
  // Only the seat the player connected with: one taken again since (a rejoin) stays.
  if (seat != seats_.end() && seat->second.match_id == match_id && seat->second.taken &&
      seat->second.generation == generation) {
    seats_.erase(seat);
  }
}

}  // namespace ricochet::server
