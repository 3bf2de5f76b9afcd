/// Placement rules over a Store (placement.h).

#include "ricochet/db/placement.h"

#include <algorithm>
#include <iterator>
#include <utility>

#include "password.h"
#include "placement_validation.h"
#include "seat_choice.h"

namespace ricochet::db {

namespace {

constexpr UnixMillis kMaxDurationMs = 3'600'000;  ///< options' upper bound: one hour

DbError invalid(std::string message) {
  return DbError{DbErrorCode::InvalidPlacement, std::move(message)};
}

DbError unknown_ticket(std::string message) {
  return DbError{DbErrorCode::UnknownTicket, std::move(message)};
}

/// Why a ticket that exists could not be claimed by this server for this account at `now`.
DbError refusal_of(const TicketRow& ticket, std::string_view server_id, AccountId account,
                   UnixMillis now) {
  if (ticket.claimed_ms)
    return unknown_ticket("the ticket was already claimed at " +
                          std::to_string(*ticket.claimed_ms) + " ms");
  if (ticket.server_id != server_id)
    return unknown_ticket("the ticket was issued for game server '" + ticket.server_id +
                          "', not this one ('" + std::string(server_id) + "')");
  if (ticket.account != account)
    return unknown_ticket("the ticket was issued to another account than " +
                          std::to_string(account));
  if (ticket.expires_ms <= now)
    return DbError{DbErrorCode::ExpiredTicket,
                   "the ticket expired at " + std::to_string(ticket.expires_ms) + " ms (now " +
                       std::to_string(now) + "); ask for a new assignment"};
  // Claimed by someone else between the claim and this read.
  return unknown_ticket("the ticket was claimed at the same moment by another request");
}

}  // namespace

Placement::Placement(Store& store, PlacementOptions options)
    : store_(store), options_(std::move(options)), refusals_(options_.on_refusal) {}

DbStatus Placement::check_options() const {
  const std::pair<const char*, UnixMillis> durations[] = {
      {"server_ttl_ms", options_.server_ttl_ms},
      {"ticket_lifetime_ms", options_.ticket_lifetime_ms}};
  for (const auto& [name, value] : durations)
    if (value < 1 || value > kMaxDurationMs)
      return invalid(std::string("PlacementOptions::") + name + " must be 1.." +
                     std::to_string(kMaxDurationMs) + " ms, got " + std::to_string(value));
  return {};
}

DbStatus Placement::heartbeat(const GameServerRow& server, const std::vector<HostedMatch>& matches,
                              UnixMillis now) {
  if (DbStatus s = check_options(); !s) return refusals_(s);
  if (std::string problem = check_heartbeat(server, matches); !problem.empty())
    return refusals_(DbStatus(invalid(std::move(problem))));
  if (server.counted_ms < 0 || server.counted_ms > now)
    return refusals_(
        DbStatus(invalid("counted_ms must be 0.." + std::to_string(now) +
                         " ms (the heartbeat's time), got " + std::to_string(server.counted_ms))));
  GameServerRow row = server;
  row.heartbeat_ms = now;
  if (row.counted_ms == 0) row.counted_ms = now;
  return refusals_(store_.transaction([&]() -> DbStatus {
    if (DbStatus s = store_.upsert_game_server(row); !s) return s;
    return store_.replace_game_server_matches(row.server_id, matches);
  }));
}

DbResult<bool> Placement::leave(std::string_view server_id) {
  if (std::string problem = check_server_id(server_id); !problem.empty())
    return refusals_(DbResult<bool>(invalid(std::move(problem))));
  return refusals_(store_.delete_game_server(server_id));
}

DbResult<std::vector<GameServerRow>> Placement::live_servers(UnixMillis now) {
  using R = DbResult<std::vector<GameServerRow>>;
  if (DbStatus s = check_options(); !s) return refusals_(R(s.error()));
  return refusals_(store_.game_servers(now - options_.server_ttl_ms));
}

DbResult<FleetDirectory> Placement::directory(UnixMillis now) {
  using R = DbResult<FleetDirectory>;
  if (DbStatus s = check_options(); !s) return refusals_(R(s.error()));
  const UnixMillis live_after = now - options_.server_ttl_ms;
  auto servers = store_.game_servers(live_after);
  if (!servers) return refusals_(R(servers.error()));
  auto matches = store_.directory_matches(live_after);
  if (!matches) return refusals_(R(matches.error()));
  return FleetDirectory{std::move(servers).value(), std::move(matches).value()};
}

DbResult<Purged> Placement::purge_stale(UnixMillis now) {
  if (DbStatus s = check_options(); !s) return refusals_(DbResult<Purged>(s.error()));
  return refusals_(atomically(store_, [&]() -> DbResult<Purged> {
    Purged purged;
    auto servers = store_.delete_game_servers_until(now - options_.server_ttl_ms);
    if (!servers) return servers.error();
    auto tickets = store_.delete_expired_tickets(now);
    if (!tickets) return tickets.error();
    purged.servers = servers.value();
    purged.tickets = tickets.value();
    return purged;
  }));
}

DbResult<Assignment> Placement::assign(AccountId account, std::string_view mode,
                                       std::string_view map, UnixMillis now) {
  using R = DbResult<Assignment>;
  if (DbStatus s = check_options(); !s) return refusals_(R(s.error()));
  if (account < 1)
    return refusals_(R(invalid("account must be >= 1, got " + std::to_string(account))));
  if (std::string problem = check_mode(mode); !problem.empty())
    return refusals_(R(invalid(std::move(problem))));
  if (!map.empty())
    if (std::string problem = check_map(map); !problem.empty())
      return refusals_(R(invalid(std::move(problem))));
  Assignment assignment;
  assignment.token = random_token();
  const std::string hash = token_hash(assignment.token);
  // Under the write lock: what is read (servers, matches, held seats) cannot change before the
  // ticket is in, so two servers assigning at once cannot both take the last seat.
  return refusals_(atomically(store_, [&]() -> R {
    if (auto dropped = store_.delete_unclaimed_tickets_of(account); !dropped)
      return dropped.error();
    const UnixMillis live_after = now - options_.server_ttl_ms;
    auto servers = store_.game_servers(live_after);
    if (!servers) return servers.error();
    auto matches = store_.directory_matches(live_after);
    if (!matches) return matches.error();
    auto held = store_.held_seats(now);
    if (!held) return held.error();
    auto choice = choose_seat(servers.value(), matches.value(), held.value(), mode, map);
    if (!choice) return choice.error();
    const GameServerRow& server = servers.value()[choice.value().server];
    TicketRow ticket;
    ticket.token_hash = hash;
    ticket.account = account;
    ticket.server_id = server.server_id;
    ticket.match_id = choice.value().match_id;
    ticket.mode = std::string(mode);
    ticket.map = std::string(choice.value().map);
    ticket.created_ms = now;
    ticket.expires_ms = now + options_.ticket_lifetime_ms;
    if (DbStatus s = store_.insert_ticket(ticket); !s) return s.error();
    assignment.server_id = server.server_id;
    assignment.host = server.host;
    assignment.control_port = server.control_port;
    assignment.game_port = server.game_port;
    assignment.certificate_sha256 = server.certificate_sha256;
    assignment.match_id = ticket.match_id;
    assignment.mode = ticket.mode;
    assignment.map = ticket.map;
    assignment.expires_ms = ticket.expires_ms;
    return assignment;
  }));
}

DbResult<ClaimedTicket> Placement::claim(std::string_view token, std::string_view server_id,
                                         AccountId account, UnixMillis now) {
  using R = DbResult<ClaimedTicket>;
  const std::string hash = token_hash(token);
  if (hash.empty())
    return refusals_(R(unknown_ticket("a ticket token is " + std::to_string(2 * kTokenBytes) +
                                      " lowercase hex digits, got " + std::to_string(token.size()) +
                                      " characters")));
  if (std::string problem = check_server_id(server_id); !problem.empty())
    return refusals_(R(invalid(std::move(problem))));
  auto claimed = store_.claim_ticket(hash, server_id, account, now);
  if (!claimed) return refusals_(R(claimed.error()));
  if (claimed.value()) return std::move(*claimed.value());
  auto ticket = store_.find_ticket(hash);
  if (!ticket) return refusals_(R(ticket.error()));
  if (!ticket.value())
    return refusals_(R(unknown_ticket(
        "no such ticket: never issued, replaced by a newer one, or its server left")));
  return refusals_(R(refusal_of(*ticket.value(), server_id, account, now)));
}

DbResult<std::vector<HeldSeats>> Placement::held_seats(std::string_view server_id, UnixMillis now) {
  using R = DbResult<std::vector<HeldSeats>>;
  if (std::string problem = check_server_id(server_id); !problem.empty())
    return refusals_(R(invalid(std::move(problem))));
  auto all = store_.held_seats(now);
  if (!all) return refusals_(R(all.error()));
  std::vector<HeldSeats> mine;
  std::copy_if(all.value().begin(), all.value().end(), std::back_inserter(mine),
               [&](const HeldSeats& h) { return h.server_id == server_id; });
  return mine;
}

}  // namespace ricochet::db
