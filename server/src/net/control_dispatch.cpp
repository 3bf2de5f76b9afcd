// The requests of a control session: each turns a validated ClientMessage into the call on the
// DB worker or the match directory and the reply (or Error) the client gets.

#include <spdlog/spdlog.h>

#include <algorithm>
#include <boost/asio/as_tuple.hpp>
#include <boost/asio/ip/address.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/this_coro.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <chrono>
#include <climits>
#include <optional>

#include "control_session.h"
#include "ricochet/proto/chat_text.h"

namespace ricochet::server {
namespace asio = boost::asio;
namespace {

/// Runs `start(post, done)` (a DbWorker call) and resumes with what `done` receives. The
/// completion is posted to the coroutine's executor (the strand), where it stores the result
/// and wakes the coroutine through a timer.
template <class R, class Start>
asio::awaitable<R> await_db(Start start) {
  struct Pending {
    explicit Pending(const asio::any_io_executor& executor) : wake(executor) {}
    std::optional<R> result;
    asio::steady_timer wake;
  };
  auto executor = co_await asio::this_coro::executor;
  auto pending = std::make_shared<Pending>(executor);
  pending->wake.expires_at(asio::steady_timer::time_point::max());
  db::Post post = [executor](std::function<void()> completion) {
    asio::post(executor, std::move(completion));
  };
  start(std::move(post), [pending](R result) {
    pending->result.emplace(std::move(result));
    pending->wake.cancel();
  });
  while (!pending->result) co_await pending->wake.async_wait(asio::as_tuple(asio::use_awaitable));
  co_return std::move(*pending->result);
}

db::UnixMillis unix_now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

wire::ServerMessage error_reply(wire::ErrorCode code, std::string message) {
  wire::ServerMessage reply;
  reply.mutable_error()->set_code(code);
  reply.mutable_error()->set_message(std::move(message));
  return reply;
}

wire::ServerMessage error_reply(const db::DbError& error) {
  switch (error.code) {
    case db::DbErrorCode::InvalidUsername:
      return error_reply(wire::INVALID_USERNAME, error.message);
    case db::DbErrorCode::DuplicateUsername:
      return error_reply(wire::DUPLICATE_USERNAME, error.message);
    case db::DbErrorCode::EmptyPassword:
    case db::DbErrorCode::PasswordTooShort:
    case db::DbErrorCode::PasswordTooLong:
      return error_reply(wire::INVALID_PASSWORD, error.message);
    case db::DbErrorCode::WrongCredentials:
      return error_reply(wire::WRONG_CREDENTIALS, error.message);
    case db::DbErrorCode::AccountBanned:
      return error_reply(wire::ACCOUNT_BANNED, error.message);
    case db::DbErrorCode::UnknownAccount:
    case db::DbErrorCode::UnknownSession:
      return error_reply(wire::UNKNOWN_SESSION, error.message);
    case db::DbErrorCode::ExpiredSession:
      return error_reply(wire::EXPIRED_SESSION, error.message);
    case db::DbErrorCode::RateLimited:
      return error_reply(wire::LOGIN_RATE_LIMITED, error.message);
    case db::DbErrorCode::QueueFull:
    case db::DbErrorCode::Busy:
      return error_reply(wire::SERVER_BUSY, error.message);
    case db::DbErrorCode::Unavailable:  // the database server is down or unreachable: retryable
      // Its message names the database's host: logged here, not sent.
      spdlog::warn("control: database unavailable: {}", error.message);
      return error_reply(wire::SERVER_BUSY, "the database is unavailable; retry after a moment");
    case db::DbErrorCode::Stopped:
      return error_reply(wire::SHUTTING_DOWN, error.message);
    case db::DbErrorCode::NoServerAvailable:
      return error_reply(wire::NO_SERVER_AVAILABLE, error.message);
    case db::DbErrorCode::UnknownModeOrMap:
      return error_reply(wire::UNKNOWN_MODE_OR_MAP, error.message);
    case db::DbErrorCode::UnknownTicket:
      return error_reply(wire::UNKNOWN_TICKET, error.message);
    case db::DbErrorCode::ExpiredTicket:
      return error_reply(wire::EXPIRED_TICKET, error.message);
    case db::DbErrorCode::InvalidPlacement:
      return error_reply(wire::INVALID_REQUEST, error.message);
    default:
      break;
  }
  // Storage failures name files and internals: logged here, not sent.
  spdlog::warn("control: database error {}: {}", db::to_string(error.code), error.message);
  return error_reply(wire::INTERNAL, std::string("the database failed (") +
                                         db::to_string(error.code) + "); try again later");
}

wire::ServerMessage error_reply(const DirectoryError& error) {
  switch (error.code) {
    case DirectoryErrorCode::MatchNotFound:
      return error_reply(wire::MATCH_NOT_FOUND, error.message);
    case DirectoryErrorCode::MatchFull:
      return error_reply(wire::MATCH_FULL, error.message);
    case DirectoryErrorCode::AlreadyInMatch:
      return error_reply(wire::ALREADY_IN_MATCH, error.message);
    case DirectoryErrorCode::NotInMatch:
      return error_reply(wire::NOT_IN_MATCH, error.message);
    case DirectoryErrorCode::InvalidRequest:
      return error_reply(wire::INVALID_REQUEST, error.message);
    case DirectoryErrorCode::TooManyMatches:
      return error_reply(wire::TOO_MANY_MATCHES, error.message);
    case DirectoryErrorCode::ShuttingDown:
      return error_reply(wire::SHUTTING_DOWN, error.message);
    case DirectoryErrorCode::RateLimited:
      return error_reply(wire::RATE_LIMITED, error.message);
    case DirectoryErrorCode::AddressSeatLimit:
      return error_reply(wire::ADDRESS_SEAT_LIMIT, error.message);
    case DirectoryErrorCode::CreateRateLimited:
      return error_reply(wire::CREATE_RATE_LIMITED, error.message);
  }
  return error_reply(wire::INTERNAL, error.message);
}

/// What the seat limits count the peer under (proto::host_key); `address` is the text the
/// control server took from the socket (IPv4-mapped IPv6 counts as its IPv4 address).
proto::HostKey host_key_of(const std::string& address) {
  boost::system::error_code error;
  const asio::ip::address ip = asio::ip::make_address(address, error);
  proto::Address out;
  if (error) return proto::host_key(out);  // not from a socket: tests' fake peers
  if (ip.is_v4()) {
    const auto bytes = ip.to_v4().to_bytes();
    std::copy(bytes.begin(), bytes.end(), out.ip.begin());
  } else {
    const auto bytes = ip.to_v6().to_bytes();
    std::copy(bytes.begin(), bytes.end(), out.ip.begin());
    out.v6 = true;
  }
  return proto::host_key(out);
}

/// How a find_match the database refused is counted.
TicketResult ticket_result(db::DbErrorCode code) {
  switch (code) {
    case db::DbErrorCode::NoServerAvailable:
      return TicketResult::NoServerAvailable;
    case db::DbErrorCode::UnknownModeOrMap:
      return TicketResult::UnknownModeOrMap;
    case db::DbErrorCode::InvalidPlacement:
      return TicketResult::InvalidRequest;
    case db::DbErrorCode::QueueFull:
    case db::DbErrorCode::Busy:
    case db::DbErrorCode::Unavailable:
      return TicketResult::ServerBusy;
    default:
      return TicketResult::Failed;
  }
}

/// "host:port", the host in brackets when it is an IPv6 address.
std::string connection_of(const std::string& host, std::int32_t port) {
  const bool v6 = host.find(':') != std::string::npos;
  return (v6 ? "[" + host + "]" : host) + ":" + std::to_string(port);
}

void fill(const MatchSummary& summary, wire::MatchInfo& info) {
  info.set_match_id(summary.id);
  info.set_name(summary.name);
  info.set_mode(summary.mode);
  info.set_map(summary.map);
  info.set_players(static_cast<std::uint32_t>(std::max(summary.players, 0)));
  info.set_max_players(static_cast<std::uint32_t>(std::max(summary.max_players, 0)));
}

}  // namespace

asio::awaitable<wire::ServerMessage> ControlSession::dispatch(const wire::ClientMessage& message) {
  switch (message.body_case()) {
    case wire::ClientMessage::kRegisterAccount:
      co_return co_await register_account(message.register_account());
    case wire::ClientMessage::kLogin:
      co_return co_await login(message.login());
    case wire::ClientMessage::kResume:
      co_return co_await resume(message.resume());
    case wire::ClientMessage::kListMatches:
      co_return list_matches();
    case wire::ClientMessage::kCreateMatch:
      co_return create_match(message.create_match());
    case wire::ClientMessage::kJoinMatch:
      co_return co_await join_match(message.join_match());
    case wire::ClientMessage::kLeaveMatch:
      co_return leave_match();
    case wire::ClientMessage::kChat:
      co_return chat(message.chat());
    case wire::ClientMessage::kPing:
      co_return pong(message.ping());
    case wire::ClientMessage::kLogout:
      co_return co_await logout();
    case wire::ClientMessage::kFindMatch:
      co_return co_await find_match(message.find_match());
    case wire::ClientMessage::BODY_NOT_SET:
      break;
  }
  co_return error_reply(wire::MALFORMED, "the ClientMessage has no body set in its oneof");
}

asio::awaitable<wire::ServerMessage> ControlSession::register_account(
    const wire::RegisterRequest& request) {
  const db::DbResult<db::AccountId> result =
      co_await await_db<db::DbResult<db::AccountId>>([&](db::Post post, auto done) {
        context_.db.register_account(request.username(), request.password(), host_key_,
                                     unix_now_ms(), std::move(post), std::move(done));
      });
  if (!result.ok())
    co_return account_refusal(result.error(), ControlRefusal::RegistrationRateLimited);
  wire::ServerMessage reply;
  reply.mutable_register_account()->set_account_id(static_cast<std::uint64_t>(result.value()));
  co_return reply;
}

asio::awaitable<wire::ServerMessage> ControlSession::login(const wire::LoginRequest& request) {
  const db::DbResult<db::LoginResult> result =
      co_await await_db<db::DbResult<db::LoginResult>>([&](db::Post post, auto done) {
        context_.db.login(request.username(), request.password(), host_key_, unix_now_ms(),
                          std::move(post), std::move(done));
      });
  if (!result.ok()) co_return account_refusal(result.error(), ControlRefusal::LoginRateLimited);
  if (machine_.state() != proto::ControlState::Unauthenticated) {
    co_return error_reply(wire::SHUTTING_DOWN, "the connection closed during the login");
  }
  if (context_.banned.contains(static_cast<std::uint64_t>(result.value().account))) {
    co_return error_reply(wire::ACCOUNT_BANNED, "account '" + request.username() + "' is banned");
  }
  authenticated(static_cast<std::uint64_t>(result.value().account), request.username(),
                result.value().token, "logged in as account ");
  wire::ServerMessage reply;
  wire::SessionReply& session = *reply.mutable_session();
  session.set_account_id(account_);
  session.set_username(username_);
  session.set_session_token(result.value().token);
  session.set_expires_unix_ms(result.value().expires_ms);
  co_return reply;
}

asio::awaitable<wire::ServerMessage> ControlSession::resume(const wire::ResumeRequest& request) {
  const db::DbResult<db::SessionInfo> result =
      co_await await_db<db::DbResult<db::SessionInfo>>([&](db::Post post, auto done) {
        context_.db.submit(
            [token = request.session_token(), now = unix_now_ms()](db::DbServices& services) {
              return services.accounts.check_session(token, now);
            },
            std::move(post), std::move(done));
      });
  if (!result.ok()) co_return account_refusal(result.error(), ControlRefusal::LoginRateLimited);
  if (machine_.state() != proto::ControlState::Unauthenticated) {
    co_return error_reply(wire::SHUTTING_DOWN, "the connection closed during the resume");
  }
  if (context_.banned.contains(static_cast<std::uint64_t>(result.value().account))) {
    co_return error_reply(wire::ACCOUNT_BANNED,
                          "account '" + result.value().username + "' is banned");
  }
  authenticated(static_cast<std::uint64_t>(result.value().account), result.value().username,
                request.session_token(), "resumed the session of account ");
  wire::ServerMessage reply;
  wire::SessionReply& session = *reply.mutable_session();
  session.set_account_id(account_);
  session.set_username(username_);
  session.set_expires_unix_ms(result.value().expires_ms);
  // Back in the match this sign-in joined, when its seat is still held (PROTOCOL.md, resume).
  if (const auto match_id = context_.matches.rejoin(
          account_, JoinOrigin{host_key_of(address_), id_, session_token_})) {
    session.set_match_id(*match_id);
    machine_.transition(proto::ControlState::InMatch,
                        "resumed into match " + std::to_string(*match_id));
  }
  co_return reply;
}

wire::ServerMessage ControlSession::account_refusal(const db::DbError& error,
                                                    ControlRefusal rate_limited) {
  if (error.code == db::DbErrorCode::QueueFull || error.code == db::DbErrorCode::Busy ||
      error.code == db::DbErrorCode::Unavailable) {
    refuse(ControlRefusal::ServerBusy, error.message);
    return error_reply(error);
  }
  if (error.code != db::DbErrorCode::RateLimited) return error_reply(error);
  refuse(rate_limited, error.message);
  return error_reply(rate_limited == ControlRefusal::RegistrationRateLimited
                         ? wire::REGISTRATION_RATE_LIMITED
                         : wire::LOGIN_RATE_LIMITED,
                     error.message);
}

void ControlSession::authenticated(std::uint64_t account, std::string username, std::string token,
                                   std::string_view how) {
  account_ = account;
  username_ = std::move(username);
  session_token_ = std::move(token);
  times_.logged_in = true;
  check_deadlines();
  machine_.transition(proto::ControlState::Authenticated,
                      std::string(how) + std::to_string(account_));
}

asio::awaitable<wire::ServerMessage> ControlSession::logout() {
  const db::DbStatus revoked = co_await await_db<db::DbStatus>([&](db::Post post, auto done) {
    context_.db.submit(
        [token = session_token_](db::DbServices& services) {
          return services.accounts.revoke_session(token);
        },
        std::move(post), std::move(done));
  });
  // Already revoked or expired (a ban, a password change, another logout): logged out anyway.
  if (!revoked.ok() && revoked.error().code != db::DbErrorCode::UnknownSession)
    co_return error_reply(revoked.error());
  if (machine_.state() == proto::ControlState::Closed) {
    co_return error_reply(wire::SHUTTING_DOWN, "the connection closed during the logout");
  }
  if (machine_.state() == proto::ControlState::InMatch) (void)context_.matches.leave(account_, id_);
  machine_.transition(proto::ControlState::Unauthenticated,
                      "account " + std::to_string(account_) + " logged out");
  account_ = 0;
  username_.clear();
  session_token_.clear();
  times_.logged_in = false;
  times_.opened_at = context_.clock();  // the login deadline counts again, from now
  check_deadlines();
  wire::ServerMessage reply;
  reply.mutable_logout();
  co_return reply;
}

wire::ServerMessage ControlSession::list_matches() {
  wire::ServerMessage reply;
  wire::ListMatchesReply& list = *reply.mutable_list_matches();
  for (const MatchSummary& summary : context_.matches.list()) fill(summary, *list.add_matches());
  return reply;
}

wire::ServerMessage ControlSession::create_match(const wire::CreateMatchRequest& request) {
  CreateMatchRequest create;
  create.name = request.name();
  // Out-of-range counts stay out of range (the directory names the field); 0 is the default.
  if (request.max_players() != 0) {
    create.max_players = static_cast<int>(std::min<std::uint32_t>(request.max_players(), INT_MAX));
  }
  create.map = request.map();
  create.creator = account_;
  DirectoryResult<MatchSummary> result = context_.matches.create(create);
  if (const auto* error = std::get_if<DirectoryError>(&result)) return error_reply(*error);
  wire::ServerMessage reply;
  fill(std::get<MatchSummary>(result), *reply.mutable_create_match()->mutable_match());
  return reply;
}

asio::awaitable<wire::ServerMessage> ControlSession::find_match(
    const wire::FindMatchRequest& request) {
  FleetPlacement* placement = context_.placement;
  if (!placement) {
    co_return error_reply(wire::NO_SERVER_AVAILABLE,
                          "placement is off on this server ([placement] enabled); use "
                          "list_matches and join_match here");
  }
  if (!placement->limiter.take(account_, context_.clock())) {
    placement->counters.count(TicketResult::RateLimited);
    co_return error_reply(wire::FIND_MATCH_RATE_LIMITED,
                          "an account may ask find_match " +
                              std::to_string(static_cast<int>(FindMatchLimiter::kBurst)) +
                              " times at once, then at the server's rate; retry later");
  }
  const db::DbResult<db::Assignment> result =
      co_await await_db<db::DbResult<db::Assignment>>([&](db::Post post, auto done) {
        context_.db.submit(
            [account = static_cast<db::AccountId>(account_), mode = request.mode(),
             map = request.map(), now = unix_now_ms()](db::DbServices& services) {
              return services.placement.assign(account, mode, map, now);
            },
            std::move(post), std::move(done));
      });
  if (!result.ok()) {
    placement->counters.count(ticket_result(result.error().code));
    co_return error_reply(result.error());
  }
  placement->counters.count(TicketResult::Assigned);
  const db::Assignment& found = result.value();
  wire::ServerMessage reply;
  wire::Assignment& assignment = *reply.mutable_find_match()->mutable_assignment();
  assignment.set_connection(connection_of(found.host, found.control_port));
  assignment.set_game_port(static_cast<std::uint32_t>(found.game_port));
  assignment.set_certificate_sha256(found.certificate_sha256);
  assignment.set_match_id(static_cast<std::uint32_t>(found.match_id));
  assignment.set_mode(found.mode);
  assignment.set_map(found.map);
  assignment.set_ticket(ticket_bytes(found.token));
  assignment.set_ticket_expires_in_ms(static_cast<std::uint32_t>(
      std::clamp<db::UnixMillis>(found.expires_ms - unix_now_ms(), 0, UINT32_MAX)));
  assignment.set_on_this_server(found.server_id == placement->server_id);
  co_return reply;
}

asio::awaitable<wire::ServerMessage> ControlSession::join_match(
    const wire::JoinMatchRequest& request) {
  if (request.ticket().empty()) co_return join_seat(request.match_id(), false);
  if (!context_.placement) {
    co_return error_reply(wire::UNKNOWN_TICKET,
                          "placement is off on this server: it takes no tickets");
  }
  const std::optional<std::string> token = ticket_hex(request.ticket());
  if (!token) {
    co_return error_reply(wire::UNKNOWN_TICKET, "a ticket is " + std::to_string(kTicketBytes) +
                                                    " bytes, got " +
                                                    std::to_string(request.ticket().size()));
  }
  // In flight until this join is seated or refused (claims_in_flight.h).
  const ClaimsInFlight::Claim in_flight = context_.placement->claims.begin();
  const db::DbResult<db::ClaimedTicket> claimed =
      co_await await_db<db::DbResult<db::ClaimedTicket>>([&](db::Post post, auto done) {
        context_.db.submit(
            [token = *token, server = context_.placement->server_id,
             account = static_cast<db::AccountId>(account_),
             now = in_flight.claimed_ms()](db::DbServices& services) {
              return services.placement.claim(token, server, account, now);
            },
            std::move(post), std::move(done));
      });
  if (!claimed.ok()) co_return error_reply(claimed.error());
  if (machine_.state() == proto::ControlState::Closed) {
    co_return error_reply(wire::SHUTTING_DOWN, "the connection closed during the join");
  }
  const DirectoryResult<std::uint32_t> match = placed_match(claimed.value());
  if (const auto* error = std::get_if<DirectoryError>(&match)) co_return error_reply(*error);
  wire::ServerMessage reply = join_seat(std::get<std::uint32_t>(match), true);
  // The fleet put this player here: Agones hears of it now, before the game connection comes
  // (a direct join allocates once its player is seated: AgonesSdk::observe).
  if (reply.has_join_match() && context_.placement->players_placed) {
    context_.placement->players_placed();
  }
  co_return reply;
}

DirectoryResult<std::uint32_t> ControlSession::placed_match(const db::ClaimedTicket& ticket) {
  const std::vector<MatchSummary> hosted = context_.matches.list();
  // A ticket for a match this server no longer hosts (it ended, or rotated, after the
  // directory's last heartbeat listed it) is taken as one for a new match of its mode and map:
  // it was for this server, and it is spent; the player need not find a match again.
  if (ticket.match_id != 0 &&
      std::any_of(hosted.begin(), hosted.end(), [&](const MatchSummary& summary) {
        return summary.id == static_cast<std::uint32_t>(ticket.match_id);
      })) {
    return static_cast<std::uint32_t>(ticket.match_id);
  }
  const MatchSummary* fullest = nullptr;
  for (const MatchSummary& summary : hosted) {
    if (summary.mode != ticket.mode || (!ticket.map.empty() && summary.map != ticket.map)) continue;
    if (summary.players >= summary.max_players) continue;
    if (!fullest || summary.players > fullest->players) fullest = &summary;
  }
  if (fullest) return fullest->id;
  // Sized as the server's own matches, and opened by placement, not by this account: the
  // server-wide created-match limits bound it, the account's find_match rate bounds the account
  // (kPlacementCreator says why).
  CreateMatchRequest create;
  create.name = ticket.mode + "-placed";
  create.max_players = context_.placement->new_match_max_players;
  create.map = ticket.map;
  create.creator = kPlacementCreator;
  DirectoryResult<MatchSummary> made = context_.matches.create(create);
  if (const auto* error = std::get_if<DirectoryError>(&made)) return *error;
  return std::get<MatchSummary>(made).id;
}

wire::ServerMessage ControlSession::join_seat(std::uint32_t match_id, bool placed) {
  DirectoryResult<JoinGrant> result =
      context_.matches.join(account_, username_, match_id,
                            JoinOrigin{host_key_of(address_), id_, session_token_, placed});
  if (const auto* error = std::get_if<DirectoryError>(&result)) return error_reply(*error);
  const JoinGrant& grant = std::get<JoinGrant>(result);
  const proto::TimeUs now = context_.clock();
  const proto::TimeUs left_us = std::max<proto::TimeUs>(grant.token.expires_at - now, 0);
  wire::ServerMessage reply;
  wire::JoinMatchReply& join = *reply.mutable_join_match();
  join.set_match_id(grant.match_id);
  join.set_udp_port(grant.udp_port);
  join.set_connect_token(grant.token.connect_token.data(), grant.token.connect_token.size());
  join.set_client_to_server_key(grant.token.client_to_server.data(),
                                grant.token.client_to_server.size());
  join.set_server_to_client_key(grant.token.server_to_client.data(),
                                grant.token.server_to_client.size());
  join.set_token_expires_in_ms(static_cast<std::uint32_t>(
      std::min<proto::TimeUs>(left_us / proto::kMicrosPerMilli, UINT32_MAX)));
  join.set_timeout_s(grant.token.timeout_s);
  proto::to_wire(grant.quantization, *join.mutable_quantization());
  join.set_tick_rate_hz(static_cast<std::uint32_t>(grant.tick_rate_hz));
  join.set_snapshot_rate_hz(static_cast<std::uint32_t>(grant.snapshot_rate_hz));
  if (grant.world) *join.mutable_world() = *grant.world;
  for (const wire::WeaponSpec& weapon : grant.weapons) *join.add_weapons() = weapon;
  machine_.transition(proto::ControlState::InMatch,
                      "joined match " + std::to_string(grant.match_id));
  return reply;
}

wire::ServerMessage ControlSession::leave_match() {
  DirectoryResult<Done> result = context_.matches.leave(account_, id_);
  if (const auto* error = std::get_if<DirectoryError>(&result)) {
    if (error->code == DirectoryErrorCode::NotInMatch) {
      machine_.transition(proto::ControlState::Authenticated, "the match had already let go");
    }
    return error_reply(*error);
  }
  machine_.transition(proto::ControlState::Authenticated, "left the match");
  wire::ServerMessage reply;
  reply.mutable_leave_match();
  return reply;
}

wire::ServerMessage ControlSession::chat(const wire::ChatRequest& request) {
  if (const auto refusal = proto::check_chat_text(request.text())) {
    refuse(ControlRefusal::InvalidRequest, refusal->message);
    return error_reply(wire::INVALID_REQUEST, refusal->message);
  }
  DirectoryResult<Done> result = context_.matches.chat(account_, id_, request.text());
  if (const auto* error = std::get_if<DirectoryError>(&result)) return error_reply(*error);
  wire::ServerMessage reply;
  reply.mutable_chat();
  return reply;
}

wire::ServerMessage ControlSession::pong(const wire::Ping& request) {
  wire::ServerMessage reply;
  reply.mutable_pong()->set_client_time_us(request.client_time_us());
  reply.mutable_pong()->set_server_unix_ms(unix_now_ms());
  return reply;
}

}  // namespace ricochet::server
