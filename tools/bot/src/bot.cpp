#include "ricochet/bot/bot.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <variant>

#include "ricochet/bot/refusal_policy.h"
#include "ricochet/proto/connect_token.h"

namespace ricochet::bot {

namespace asio = boost::asio;

namespace {

constexpr double kConnectTimeoutS = 10;  ///< TCP connect and TLS handshake
/// Register and login: two Argon2id hashes, queued on the server behind every other bot's.
constexpr double kSignInTimeoutS = 60;
constexpr double kRequestTimeoutS = 10;  ///< list and join
constexpr double kResultsTimeoutS = 15;  ///< from MatchEnded to MatchResults
constexpr double kNoRoomRetryS = 1;      ///< listing again when no match has room
constexpr proto::TimeUs kRttSampleUs = proto::kMicrosPerSecond;
constexpr std::size_t kMaxRttSamples = 86400;

double seconds_between(proto::TimeUs from, proto::TimeUs to) {
  return static_cast<double>(to - from) / static_cast<double>(proto::kMicrosPerSecond);
}

double backoff_s(int attempt) {
  return std::min(8.0, 0.5 * std::pow(2.0, attempt - 1));
}

bool is_error(const wire::ServerMessage& reply, wire::ErrorCode code) {
  return reply.has_error() && reply.error().code() == code;
}

std::string text_of(const asio::ip::tcp::endpoint& endpoint) {
  const std::string host = endpoint.address().to_string();
  return (endpoint.address().is_v6() ? "[" + host + "]" : host) + ":" +
         std::to_string(endpoint.port());
}

std::string describe(const wire::ServerMessage& reply) {
  if (!reply.has_error()) return "an unexpected reply";
  return std::string(wire::ErrorCode_Name(reply.error().code())) + ": " + reply.error().message();
}

/// Empty when the join reply can be used; otherwise what is wrong with it.
std::string check_join(const wire::JoinMatchReply& join) {
  if (join.connect_token().size() != proto::kConnectTokenBytes) {
    return "connect token of " + std::to_string(join.connect_token().size()) + " bytes, expected " +
           std::to_string(proto::kConnectTokenBytes);
  }
  if (join.client_to_server_key().size() != proto::kKeyBytes ||
      join.server_to_client_key().size() != proto::kKeyBytes) {
    return "session keys must be 32 bytes each";
  }
  if (join.udp_port() == 0 || join.udp_port() > 65535) {
    return "udp_port must be 1..65535, got " + std::to_string(join.udp_port());
  }
  if (join.timeout_s() < proto::kMinTimeoutS || join.timeout_s() > proto::kMaxTimeoutS) {
    return "timeout_s must be 1..60, got " + std::to_string(join.timeout_s());
  }
  if (join.tick_rate_hz() < 10 || join.tick_rate_hz() > 128) {
    return "tick_rate_hz must be 10..128, got " + std::to_string(join.tick_rate_hz());
  }
  if (join.snapshot_rate_hz() < 1 || join.snapshot_rate_hz() > join.tick_rate_hz()) {
    return "snapshot_rate_hz must be 1..tick_rate_hz, got " +
           std::to_string(join.snapshot_rate_hz());
  }
  return {};
}

}  // namespace

const char* name(BotState state) {
  switch (state) {
    case BotState::Connecting:
      return "connecting";
    case BotState::SigningIn:
      return "signing_in";
    case BotState::Joining:
      return "joining";
    case BotState::Handshaking:
      return "handshaking";
    case BotState::Playing:
      return "playing";
    case BotState::Reconnecting:
      return "reconnecting";
    case BotState::Done:
      return "done";
  }
  return "unknown";
}

template <class Handler>
auto Bot::guarded(Handler handler) {
  return [alive = std::weak_ptr<bool>(alive_), handler = std::move(handler)](auto&&... args) {
    if (alive.expired()) return;
    handler(std::forward<decltype(args)>(args)...);
  };
}

Bot::Bot(asio::io_context& io, asio::ssl::context& tls, ServerTrust& trust, BotConfig config)
    : io_(io),
      tls_(tls),
      trust_(trust),
      config_(std::move(config)),
      retry_random_(static_cast<std::uint_fast32_t>(config_.seed)),
      brain_(config_.skill, config_.seed),
      deadline_(io),
      tick_timer_(io),
      alive_(std::make_shared<bool>(true)) {
  home_ = {{asio::ip::make_address(config_.host), config_.control_port}, &trust_, 0};
  at_ = home_;
  if (!config_.find_match.empty()) {
    // validate() accepted it.
    wanted_ = std::get<MatchWanted>(parse_match_wanted(config_.find_match));
  }
  if (!config_.bind_address.empty()) local_address_ = asio::ip::make_address(config_.bind_address);
}

Bot::~Bot() {
  if (control_) control_->close();
  if (game_) game_->abandon();
}

void Bot::transition(BotState to, std::string_view reason) {
  if (to == state_) {
    spdlog::debug("bot {}: {} ({})", config_.name, name(state_), reason);
    return;
  }
  spdlog::info("bot {}: {} -> {} ({})", config_.name, name(state_), name(to), reason);
  state_ = to;
}

void Bot::arm(double seconds, std::function<void()> on_expiry) {
  deadline_.expires_after(std::chrono::microseconds(static_cast<std::int64_t>(seconds * 1e6)));
  deadline_.async_wait(
      guarded([on_expiry = std::move(on_expiry)](const boost::system::error_code& error) {
        if (!error) on_expiry();
      }));
}

void Bot::start() {
  started_at_us_ = steady_now_us();
  if (!config_.dump_states.empty()) {
    std::string error;
    dump_ = StateDump::create(config_.dump_states, error);
    if (!dump_) return finish("cannot dump states", error);
  }
  spdlog::info("bot {}: connecting to {}", config_.name, config_.host);
  connect_control();
}

void Bot::stop(std::string_view reason) {
  finish(reason);
}

void Bot::finish(std::string_view reason, std::string error) {
  if (state_ == BotState::Done) return;
  deadline_.cancel();
  close_game(true);
  if (control_) {
    control_->close();
    control_.reset();
  }
  if (!error.empty()) {
    spdlog::error("bot {}: {}", config_.name, error);
    if (on_failure_) on_failure_(error);
  }
  record_.error = std::move(error);
  transition(BotState::Done, reason);
  if (auto callback = std::move(on_done_)) callback();
}

void Bot::fail_attempt(const std::string& reason, Retry retry) {
  if (state_ == BotState::Done) return;
  if (on_failure_) on_failure_(reason);
  if (++failed_attempts_ > config_.max_reconnect_attempts) {
    return finish("giving up", "gave up after " + std::to_string(config_.max_reconnect_attempts) +
                                   " failed attempts in a row; the last: " + reason);
  }
  close_game(false);
  spdlog::warn("bot {}: {} (attempt {} of {})", config_.name, reason, failed_attempts_,
               config_.max_reconnect_attempts);
  if (retry == Retry::NewConnection && control_) {
    // A reply may still be on its way; a new connection cannot mistake it for its own.
    control_->close();
    control_.reset();
  }
  transition(BotState::Reconnecting, reason);
  arm(backoff_s(failed_attempts_), [this] {
    if (!control_ || !control_->is_open()) {
      transition(BotState::Connecting, "retrying the control channel");
      connect_control();
    } else if (!signed_in_) {
      transition(BotState::SigningIn, "retrying the sign-in");
      sign_in();
    } else {
      seek_seat();
    }
  });
}

void Bot::retry_busy(const std::string& reason) {
  if (state_ == BotState::Done) return;
  ++busy_retries_;
  const double wait =
      busy_backoff_s(busy_retries_, std::uniform_real_distribution<double>(0, 1)(retry_random_));
  spdlog::info("bot {}: {}; signing in again in {:.1f} s (busy {} times in a row)", config_.name,
               reason, wait, busy_retries_);
  arm(wait, [this] {
    if (!control_ || !control_->is_open()) {
      transition(BotState::Connecting, "retrying the control channel");
      connect_control();
    } else {
      sign_in();
    }
  });
}

void Bot::reconnect(const std::string& reason) {
  close_game(false);
  lost_at_us_ = steady_now_us();
  transition(BotState::Reconnecting, reason);
  if (control_ && control_->is_open()) {
    seek_seat();
  } else {
    fail_attempt("the control channel is down; " + reason, Retry::NewConnection);
  }
}

// --- control channel ---

void Bot::connect_control() {
  if (control_) control_->close();
  signed_in_ = false;
  // A ticket that expired while its server could not be reached holds the bot there no more.
  if (ticket_ && !ticket_->ticket_usable(steady_now_us())) ticket_.reset();
  // Nothing holds the bot where it was placed: it asks through the first server again.
  if (unplaced()) at_ = home_;
  proto::ControlClientConfig protocol;  // its defaults: sign-in's minute, a ping every 30 s
  protocol.on_transition = [name = config_.name](proto::ControlState from, proto::ControlState to,
                                                 std::string_view reason) {
    spdlog::debug("bot {}: control {} -> {} ({})", name, proto::name(from), proto::name(to),
                  reason);
  };
  control_ = std::make_shared<ControlClient>(
      io_, tls_, *at_.trust,
      ControlClient::Callbacks{
          guarded([this](const std::string& error) { on_control_ready(error); }),
          guarded([this](const wire::MatchResults& results) { on_match_results(results); }),
          guarded([this](const std::string& reason) { on_control_closed(reason); })},
      std::move(protocol));
  // A bind address of the other family (an assigned server's) is left to the system.
  const bool same_family =
      local_address_.is_unspecified() || local_address_.is_v4() == at_.control.address().is_v4();
  control_->connect(at_.control, same_family ? local_address_ : asio::ip::address{});
  arm(kConnectTimeoutS, [this] {
    fail_attempt("timed out connecting to the control channel", Retry::NewConnection);
  });
}

void Bot::on_control_ready(const std::string& error) {
  if (!error.empty()) {
    if (control_ && control_->untrusted()) return finish("server not trusted", error);
    return fail_attempt(error, Retry::NewConnection);
  }
  transition(BotState::SigningIn, "TLS 1.3 up, server certificate trusted");
  sign_in();
}

void Bot::on_match_results(const wire::MatchResults& results) {
  record_.results.push_back(results);
  ++metrics_.matches;
  spdlog::info("bot {}: results of match {} ({} players{}{})", config_.name, results.match_id(),
               results.players_size(), results.aborted() ? ", aborted" : "",
               results.record_pending() ? ", its record pending: no ratings yet" : "");
  if (awaiting_results_) after_match();
}

void Bot::on_control_closed(const std::string& reason) {
  if (control_ && control_->refused_server()) ++metrics_.bad_control;
  control_.reset();
  switch (state_) {
    case BotState::Playing:
    case BotState::Handshaking:
      // The game channel does not need it; a later reconnect opens a new one.
      spdlog::warn("bot {}: control channel lost ({}); playing on", config_.name, reason);
      break;
    case BotState::Done:
      break;
    default:
      fail_attempt("control channel lost: " + reason, Retry::NewConnection);
      break;
  }
}

void Bot::sign_in() {
  arm(kSignInTimeoutS, [this] { fail_attempt("timed out signing in", Retry::NewConnection); });
  if (!session_token_.empty()) {
    wire::ClientMessage resume;
    resume.mutable_resume()->set_session_token(session_token_);
    control_->request(
        std::move(resume), guarded([this](const wire::ServerMessage& reply) {
          if (is_error(reply, wire::UNKNOWN_SESSION) || is_error(reply, wire::EXPIRED_SESSION)) {
            session_token_.clear();
            return sign_in();
          }
          if (reply.has_session()) ++metrics_.resumes;
          on_session(reply);
        }));
    return;
  }
  // Register first: a name already taken costs no failed login (those are rate limited).
  wire::ClientMessage registration;
  registration.mutable_register_account()->set_username(config_.name);
  registration.mutable_register_account()->set_password(config_.password);
  control_->request(
      std::move(registration), guarded([this](const wire::ServerMessage& reply) {
        // Rate limited: an earlier attempt whose reply was lost (a sign-in that
        // timed out on a busy server) may have registered the account; the login
        // tells.
        if (reply.has_register_account() || is_error(reply, wire::DUPLICATE_USERNAME) ||
            is_error(reply, wire::REGISTRATION_RATE_LIMITED))
          return log_in();
        if (is_error(reply, wire::SERVER_BUSY))
          return retry_busy("registration: " + describe(reply));
        finish("registration refused", "cannot register " + config_.name + ": " + describe(reply));
      }));
}

void Bot::log_in() {
  wire::ClientMessage login;
  login.mutable_login()->set_username(config_.name);
  login.mutable_login()->set_password(config_.password);
  control_->request(std::move(login),
                    guarded([this](const wire::ServerMessage& reply) { on_session(reply); }));
}

void Bot::on_session(const wire::ServerMessage& reply) {
  if (!reply.has_session()) {
    if (is_error(reply, wire::SERVER_BUSY)) return retry_busy("login: " + describe(reply));
    if (is_error(reply, wire::LOGIN_RATE_LIMITED)) {
      return fail_attempt("login: " + describe(reply), Retry::SameConnection);
    }
    return finish("login refused", "cannot log in as " + config_.name + ": " + describe(reply) +
                                       (is_error(reply, wire::WRONG_CREDENTIALS)
                                            ? " (the account exists with another --password)"
                                            : ""));
  }
  signed_in_ = true;
  busy_retries_ = 0;
  record_.account_id = reply.session().account_id();
  if (!reply.session().session_token().empty()) session_token_ = reply.session().session_token();
  transition(BotState::Joining, "logged in as account " + std::to_string(record_.account_id) +
                                    " on " + text_of(at_.control));
  seek_seat();
}

void Bot::seek_seat() {
  if (unplaced() && at_.control != home_.control) {
    if (control_) {
      control_->close();
      control_.reset();
    }
    transition(BotState::Connecting, "back to " + text_of(home_.control) + " to find a match");
    return connect_control();
  }
  if (!control_ || !control_->is_open())
    return fail_attempt("the control channel is down", Retry::NewConnection);
  arm(kRequestTimeoutS,
      [this] { fail_attempt("timed out joining a match", Retry::NewConnection); });
  if (match_id_ != 0) return join(match_id_);
  if (config_.match_id != 0) return join(config_.match_id);
  if (wanted_) return ticket_ ? join_with_ticket() : find_match();
  join_listed();
}

void Bot::join_listed() {
  wire::ClientMessage list;
  list.mutable_list_matches();
  control_->request(std::move(list), guarded([this](const wire::ServerMessage& reply) {
                      if (!reply.has_list_matches())
                        return fail_attempt("list_matches: " + describe(reply),
                                            Retry::SameConnection);
                      for (const wire::MatchInfo& match : reply.list_matches().matches()) {
                        if (match.match_id() != 0 && match.players() < match.max_players()) {
                          return join(match.match_id());
                        }
                      }
                      spdlog::info("bot {}: no match has room; listing again in {} s", config_.name,
                                   kNoRoomRetryS);
                      arm(kNoRoomRetryS, [this] { seek_seat(); });
                    }));
}

void Bot::join(std::uint32_t match_id) {
  wire::ClientMessage request;
  request.mutable_join_match()->set_match_id(match_id);
  control_->request(std::move(request),
                    guarded([this](const wire::ServerMessage& reply) { on_join(reply); }));
}

void Bot::on_join(const wire::ServerMessage& reply) {
  const bool with_ticket = ticket_.has_value();
  if (reply.has_join_match()) {
    if (with_ticket) {
      record_.placements.push_back({text_of(at_.control), reply.join_match().match_id()});
      ticket_.reset();
    }
    return open_game(reply.join_match());
  }
  if (with_ticket) return on_ticket_refused(reply);
  if (is_error(reply, wire::MATCH_NOT_FOUND) && match_id_ != 0) {
    // The match we held a seat in is over (a rotation); find another.
    match_id_ = 0;
    return seek_seat();
  }
  if (config_.match_id != 0 &&
      (is_error(reply, wire::MATCH_NOT_FOUND) || is_error(reply, wire::MATCH_FULL))) {
    return finish("cannot join",
                  "cannot join match " + std::to_string(config_.match_id) + ": " + describe(reply));
  }
  if (reply.has_error() && refusal_action(reply.error().code()) == RefusalAction::WaitForRoom) {
    // No seat now (the match, or this address, holds its most): seats free as players leave.
    spdlog::info("bot {}: join_match: {}; looking again in {} s", config_.name, describe(reply),
                 kNoRoomRetryS);
    report_refusal("join_match: " + describe(reply));
    return arm(kNoRoomRetryS, [this] { seek_seat(); });
  }
  if (is_error(reply, wire::ALREADY_IN_MATCH)) {
    return leave_then_seek();
  }
  fail_attempt("join_match: " + describe(reply), Retry::SameConnection);
}

// --- placement ---

void Bot::find_match() {
  if (finding_since_us_ < 0) finding_since_us_ = steady_now_us();
  wire::ClientMessage request;
  request.mutable_find_match()->set_mode(wanted_->mode);
  request.mutable_find_match()->set_map(wanted_->map);
  control_->request(std::move(request),
                    guarded([this](const wire::ServerMessage& reply) { on_find_match(reply); }));
}

void Bot::on_find_match(const wire::ServerMessage& reply) {
  if (reply.has_find_match()) {
    auto read = read_assignment(reply.find_match().assignment(), steady_now_us());
    if (const auto* problem = std::get_if<std::string>(&read)) {
      ++metrics_.bad_control;
      return fail_attempt("unusable assignment: " + *problem, Retry::SameConnection);
    }
    ticket_ = std::get<Assigned>(std::move(read));
    if (ticket_->on_this_server) return join_with_ticket();
    const auto pin =
        assigned_trust_
            .try_emplace(ticket_->fingerprint,
                         ServerTrust::pinned(ticket_->fingerprint,
                                             "the assignment from " + text_of(home_.control)))
            .first;
    const ServerTarget there{
        {ticket_->host, ticket_->control_port}, &pin->second, ticket_->game_port};
    if (control_) {
      control_->close();
      control_.reset();
    }
    at_ = there;
    transition(BotState::Connecting, "assigned to " + text_of(at_.control) + " (match " +
                                         std::to_string(ticket_->match_id) + ")");
    return connect_control();
  }
  const wire::ErrorCode code = reply.has_error() ? reply.error().code() : wire::INTERNAL;
  switch (placement_action(code)) {
    case PlacementAction::RetryLater: {
      const double wait =
          retry_later_s(std::uniform_real_distribution<double>(0, 1)(retry_random_));
      spdlog::info("bot {}: find_match: {}; asking again in {:.1f} s", config_.name,
                   describe(reply), wait);
      report_refusal("find_match: " + describe(reply));
      return arm(wait, [this] { seek_seat(); });
    }
    case PlacementAction::GiveUp:
      return finish("cannot be placed",
                    "find_match " + config_.find_match + " refused: " + describe(reply));
    case PlacementAction::FindAgain:
      return find_again("find_match: " + describe(reply));
    case PlacementAction::FailedAttempt:
      break;
  }
  fail_attempt("find_match: " + describe(reply), Retry::SameConnection);
}

void Bot::join_with_ticket() {
  if (!ticket_->ticket_usable(steady_now_us())) {
    ticket_.reset();
    return find_again("the ticket expired before it was presented");
  }
  wire::ClientMessage request;
  request.mutable_join_match()->set_ticket(ticket_->ticket);
  control_->request(std::move(request),
                    guarded([this](const wire::ServerMessage& reply) { on_join(reply); }));
}

void Bot::report_refusal(const std::string& reason) {
  if (on_failure_) on_failure_(reason);
}

void Bot::leave_then_seek() {
  // ALREADY_IN_MATCH: from this connection's match, leave (a resume with the token that took the
  // seat is back in its match, PROTOCOL.md); a seat another login took cannot be left from here
  // (Authenticated): it lapses with its token, so try again later.
  wire::ClientMessage leave;
  leave.mutable_leave_match();
  if (!control_->request(std::move(leave),
                         guarded([this](const wire::ServerMessage&) { seek_seat(); }))) {
    arm(kNoRoomRetryS, [this] { seek_seat(); });
  }
}

void Bot::on_ticket_refused(const wire::ServerMessage& reply) {
  ticket_.reset();  // claimed or refused: never presented twice
  if (is_error(reply, wire::ALREADY_IN_MATCH)) {
    return leave_then_seek();  // seated elsewhere (a seat of an earlier connection)
  }
  const wire::ErrorCode code = reply.has_error() ? reply.error().code() : wire::INTERNAL;
  switch (placement_action(code)) {
    case PlacementAction::FindAgain:
      return find_again("join_match with the ticket: " + describe(reply));
    case PlacementAction::RetryLater: {
      const double wait =
          retry_later_s(std::uniform_real_distribution<double>(0, 1)(retry_random_));
      report_refusal("join_match with the ticket: " + describe(reply));
      return arm(wait, [this] { seek_seat(); });
    }
    case PlacementAction::GiveUp:
      return finish("cannot be placed", "join_match with the ticket of find_match " +
                                            config_.find_match + " refused: " + describe(reply));
    case PlacementAction::FailedAttempt:
      break;
  }
  fail_attempt("join_match with the ticket: " + describe(reply), Retry::SameConnection);
}

void Bot::find_again(const std::string& reason) {
  report_refusal(reason);
  if (++find_again_ > kMaxFindAgainInARow) {
    return finish("giving up", "placed " + std::to_string(kMaxFindAgainInARow) +
                                   " times in a row without a seat; the last: " + reason);
  }
  const double wait =
      find_again_s(find_again_, std::uniform_real_distribution<double>(0, 1)(retry_random_));
  spdlog::info("bot {}: {}; finding a match again in {:.1f} s ({} in a row)", config_.name, reason,
               wait, find_again_);
  transition(BotState::Joining, reason);
  arm(wait, [this] { seek_seat(); });
}

void Bot::after_match() {
  awaiting_results_ = false;
  match_id_ = 0;  // the seat ended with the match; the rotation opens the next one
  if (config_.matches > 0 && metrics_.matches >= config_.matches) {
    return finish("finished " + std::to_string(metrics_.matches) + " matches");
  }
  transition(BotState::Joining, "the next match");
  if (unplaced() || (control_ && control_->is_open())) {
    seek_seat();
  } else {
    fail_attempt("the control channel is down after the match", Retry::NewConnection);
  }
}

// --- game channel ---

void Bot::open_game(const wire::JoinMatchReply& reply) {
  if (const std::string problem = check_join(reply); !problem.empty()) {
    ++metrics_.bad_control;
    return fail_attempt("unusable join reply: " + problem, Retry::SameConnection);
  }
  std::string error;
  const auto spec = proto::from_wire(reply.quantization(), error);
  if (!spec) {
    ++metrics_.bad_control;
    return fail_attempt("unusable join reply: quantization " + error, Retry::SameConnection);
  }
  const std::optional<Arsenal> arsenal = arsenal_of(reply, error);
  if (!arsenal) {
    ++metrics_.bad_control;
    return fail_attempt("unusable join reply: " + error, Retry::SameConnection);
  }
  brain_.set_weapons(*arsenal);
  proto::TokenGrant grant;
  grant.connect_token.assign(reply.connect_token().begin(), reply.connect_token().end());
  std::copy_n(reply.client_to_server_key().begin(), proto::kKeyBytes,
              grant.client_to_server.begin());
  std::copy_n(reply.server_to_client_key().begin(), proto::kKeyBytes,
              grant.server_to_client.begin());
  grant.timeout_s = reply.timeout_s();
  match_id_ = reply.match_id();
  tick_rate_hz_ = reply.tick_rate_hz();
  tick_period_us_ = proto::kMicrosPerSecond / tick_rate_hz_;
  // On an assigned server, its game port from the directory (what it advertises: the bound
  // one may not be reachable from here); otherwise the join reply's.
  game_endpoint_ = {at_.control.address(), at_.game_port != 0
                                               ? at_.game_port
                                               : static_cast<std::uint16_t>(reply.udp_port())};

  close_game(false);
  feed_.emplace(*spec, static_cast<double>(reply.tick_rate_hz()) / reply.snapshot_rate_hz(),
                "bot " + config_.name);
  if (config_.predict) rendered_.emplace(reply, *spec, "bot " + config_.name);
  arrived_ = false;
  entity_recorded_ = false;
  match_over_ = false;
  auto game = std::make_shared<GameSession>(
      io_, game_endpoint_, std::move(grant),
      guarded([this](proto::ClientEvent& event) { on_game_event(event); }), config_.link,
      config_.seed);
  game_ = game;
  // The shared socket reaches IPv4 loopback servers only (FleetConfig checks the first server;
  // an assigned one elsewhere gets a socket of its own).
  const bool shareable = game_endpoint_.address().is_v4() && game_endpoint_.address().is_loopback();
  if (shared_port_ && config_.rebind_after_s == 0 && shareable) {
    if (std::string error = game->use_shared_port(shared_port_); !error.empty()) {
      game_.reset();
      feed_.reset();
      return fail_attempt(error, Retry::SameConnection);
    }
  } else if (!local_address_.is_unspecified() &&
             local_address_.is_v4() == game_endpoint_.address().is_v4()) {
    if (std::string error = game->bind_local(local_address_); !error.empty()) {
      game_.reset();
      feed_.reset();
      return fail_attempt(error, Retry::SameConnection);
    }
  }
  record_.local_ports.push_back(game->local_port());
  transition(BotState::Handshaking, "joined match " + std::to_string(match_id_) +
                                        ", game channel from local port " +
                                        std::to_string(game->local_port()));
  arm(reply.timeout_s() + 1.0,
      [this] { fail_attempt("timed out in the game handshake", Retry::SameConnection); });
  game->start();
  const proto::TimeUs now = steady_now_us();
  next_tick_us_ = now;
  if (config_.tick_phases > 0) {
    // On the shared grid: the last grid point of this bot's phase at or before now.
    const proto::TimeUs phase = tick_period_us_ *
                                static_cast<proto::TimeUs>(config_.seed % config_.tick_phases) /
                                config_.tick_phases;
    next_tick_us_ = (now - phase) / tick_period_us_ * tick_period_us_ + phase;
  }
  if (game_ == game) schedule_tick(now);
}

void Bot::on_game_event(proto::ClientEvent& event) {
  if (auto* payload = std::get_if<proto::ClientUnreliable>(&event)) {
    on_payload(payload->bytes, steady_now_us());
  } else if (auto* reliable = std::get_if<proto::ClientReliable>(&event)) {
    on_reliable(reliable->bytes);
  } else if (auto* lost = std::get_if<proto::ClientDisconnected>(&event)) {
    on_game_lost(lost->reason);
  } else if (std::holds_alternative<proto::ClientConnected>(event)) {
    deadline_.cancel();
    failed_attempts_ = 0;
    find_again_ = 0;
    connected_at_us_ = steady_now_us();
    next_rtt_sample_us_ = connected_at_us_ + kRttSampleUs;
    if (!record_.entity_ids.empty()) ++metrics_.reconnects;
    transition(BotState::Playing, "game channel connected");
  }
}

void Bot::on_payload(std::span<const std::uint8_t> bytes, proto::TimeUs now) {
  const bool snapshot = feed_->read_payload(bytes);
  if (feed_->own_entity_id() != 0) own_entity_id_ = feed_->own_entity_id();
  if (!entity_recorded_ && feed_->own_entity_id() != 0) {
    entity_recorded_ = true;
    record_.entity_ids.push_back(own_entity_id_);
    if (arrived_ && record_.arrivals.back().entity_id == 0) {
      record_.arrivals.back().entity_id = own_entity_id_;
    }
  }
  if (!snapshot) return;
  if (dump_) dump_->write(feed_->view());
  if (rendered_) rendered_->on_snapshot(*feed_, seconds_between(started_at_us_, now));
  if (metrics_.first_snapshot_ms < 0) {
    metrics_.first_snapshot_ms = seconds_between(started_at_us_, now) * 1000;
  }
  if (finding_since_us_ >= 0) {
    metrics_.placement_ms.push_back(seconds_between(finding_since_us_, now) * 1000);
    finding_since_us_ = -1;
  }
  if (lost_at_us_ >= 0) {
    metrics_.last_reconnect_ms = seconds_between(lost_at_us_, now) * 1000;
    lost_at_us_ = -1;
  }
}

void Bot::on_reliable(std::span<const std::uint8_t> bytes) {
  const std::optional<wire::GameEvent> read = feed_->read_event(bytes);
  if (!read) return;
  const wire::GameEvent& event = *read;
  switch (event.event_case()) {
    case wire::GameEvent::kKill:
      on_kill(event.kill());
      break;
    case wire::GameEvent::kHit:
      if (own_entity_id_ != 0 && event.hit().attacker_entity_id() == own_entity_id_) {
        ++metrics_.hits_dealt;
      }
      break;
    case wire::GameEvent::kPlayerJoined:
      // Our own PlayerJoined comes last of the ones sent on arrival, before any payload.
      if (event.player_joined().name() == config_.name && own_entity_id_ == 0) {
        own_entity_id_ = event.player_joined().entity_id();
      }
      break;
    case wire::GameEvent::kMatchState: {
      const wire::MatchPhase phase = event.match_state().phase();
      if (phase == wire::MATCH_PHASE_RUNNING && phase_ != wire::MATCH_PHASE_RUNNING) {
        // Entering running resets every score. (A reconnect's arrival in a running match
        // does not: the phase did not change.)
        match_kills_ = 0;
        match_deaths_ = 0;
        score_counted_ = 0;
        record_.kills.clear();
      }
      phase_ = phase;
      if (!arrived_) {
        arrived_ = true;
        record_.arrivals.push_back({entity_recorded_ ? own_entity_id_ : 0, event.match_state(),
                                    match_kills_, match_deaths_, score_counted_});
        adopt_scores(event.match_state());
      }
      break;
    }
    case wire::GameEvent::kMatchEnded:
      record_.match_ended.push_back(event.match_ended().reason());
      match_over_ = true;
      spdlog::info("bot {}: match {} ended ({})", config_.name, match_id_,
                   wire::MatchEndReason_Name(event.match_ended().reason()));
      break;
    case wire::GameEvent::kChat:
      spdlog::debug("bot {}: chat from {}: {}", config_.name, event.chat().name(),
                    event.chat().text());
      break;
    default:
      break;
  }
}

void Bot::adopt_scores(const wire::MatchState& state) {
  if (phase_ != wire::MATCH_PHASE_RUNNING || own_entity_id_ == 0) return;
  for (const wire::PlayerScore& score : state.scores()) {
    if (score.entity_id() != own_entity_id_) continue;
    const int missed_kills = score.kills() - match_kills_;
    const int missed_deaths = score.deaths() - match_deaths_;
    if (missed_kills == 0 && missed_deaths == 0 && score.score() == score_counted_) return;
    // Kill events sent to the old connection and not yet received went with it (the reliable
    // stream is per connection); the arrival's scoreboard is the server's word.
    ++metrics_.score_resyncs;
    spdlog::info("bot {}: arrival scores kills {} deaths {} score {}, counted {} {} {}",
                 config_.name, score.kills(), score.deaths(), score.score(), match_kills_,
                 match_deaths_, score_counted_);
    metrics_.kills += missed_kills;
    metrics_.deaths += missed_deaths;
    match_kills_ = score.kills();
    match_deaths_ = score.deaths();
    score_counted_ = score.score();
    return;
  }
}

void Bot::on_kill(const wire::Kill& kill) {
  ++metrics_.kill_events;
  if (phase_ != wire::MATCH_PHASE_RUNNING) return;
  record_.kills.push_back(kill);
  const std::uint32_t me = own_entity_id_;
  if (me == 0) return;
  if (kill.victim_entity_id() == me) {
    ++metrics_.deaths;
    ++match_deaths_;
    // A suicide or a death by the world costs a point.
    if (kill.killer_entity_id() == me || kill.killer_entity_id() == 0) --score_counted_;
  } else if (kill.killer_entity_id() == me) {
    ++metrics_.kills;
    ++match_kills_;
    ++score_counted_;
  }
}

void Bot::on_game_lost(proto::DisconnectReason reason) {
  const std::string why = "game channel ended: " + std::string(proto::name(reason));
  const bool have_results =
      !record_.results.empty() && record_.results.back().match_id() == match_id_;
  // On a lossy link the MatchEnded event may never arrive before the server closes the game
  // connection; the match's results on the control channel say the same.
  if (match_over_ || have_results) {
    close_game(false);
    if (have_results) return after_match();
    awaiting_results_ = true;
    transition(BotState::Joining, why + ", waiting for the match results");
    arm(kResultsTimeoutS, [this] {
      spdlog::warn("bot {}: no MatchResults within {} s", config_.name, kResultsTimeoutS);
      after_match();
    });
    return;
  }
  if (state_ == BotState::Handshaking) return fail_attempt(why, Retry::SameConnection);
  if (on_failure_) on_failure_(why);
  reconnect(why);
}

void Bot::close_game(bool tell_server) {
  tick_timer_.cancel();
  if (!game_) return;
  const proto::TimeUs now = steady_now_us();
  add_connection(metrics_, now);
  const auto game = std::move(game_);
  game_.reset();
  feed_.reset();
  rendered_.reset();
  connected_at_us_ = 0;
  if (tell_server) {
    game->disconnect(now);
  } else {
    game->abandon();
  }
}

void Bot::schedule_tick(proto::TimeUs now) {
  next_tick_us_ += tick_period_us_;
  // After a stall, start again from now (on the grid, if any) instead of sending a burst.
  if (next_tick_us_ < now - tick_period_us_) {
    next_tick_us_ += (now - next_tick_us_) / tick_period_us_ * tick_period_us_ + tick_period_us_;
  }
  tick_timer_.expires_at(asio::steady_timer::time_point(std::chrono::microseconds(next_tick_us_)));
  tick_timer_.async_wait(guarded([this](const boost::system::error_code& error) {
    if (!error) tick();
  }));
}

void Bot::tick() {
  const auto game = game_;
  if (!game) return;
  const proto::TimeUs now = steady_now_us();
  game->update(now);
  if (game_ != game) return;  // the update ended the connection
  if (state_ != BotState::Playing) return schedule_tick(now);

  if (now >= next_rtt_sample_us_) {
    if (game->transport().rtt_us() > 0 && metrics_.rtt_ms.size() < kMaxRttSamples) {
      metrics_.rtt_ms.push_back(static_cast<double>(game->transport().rtt_us()) / 1000.0);
    }
    next_rtt_sample_us_ = now + kRttSampleUs;
  }
  if (config_.rebind_after_s > 0 && connected_at_us_ > 0 &&
      seconds_between(connected_at_us_, now) >= config_.rebind_after_s) {
    return reconnect("moving to a new local port (rebind after " +
                     std::to_string(config_.rebind_after_s) + " s)");
  }

  const double now_s = seconds_between(started_at_us_, now);
  const WorldView& seen = rendered_ ? rendered_->render(feed_->view(), now_s) : feed_->view();
  wire::Input input = brain_.decide(seen, feed_->status(), now_s);
  if (input.weapon_slot() != 0) ++metrics_.weapon_switches;
  if (rendered_) rendered_->stamp(input);
  const std::string& bytes = feed_->write_payload(std::move(input));
  if (rendered_) rendered_->on_input(feed_->inputs().unacknowledged().back());
  if (game->send(std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()),
                 now)) {
    ++metrics_.inputs_sent;
  }
  if (game_ == game) schedule_tick(now);
}

void Bot::add_connection(BotMetrics& out, proto::TimeUs now) const {
  if (game_) {
    out.add_transport(game_->transport().counters(),
                      connected_at_us_ > 0 ? seconds_between(connected_at_us_, now) : 0.0);
    out.send_failures += game_->send_failures();
    const proto::GameClient::ReceiveStats received = game_->transport().receive_stats();
    out.server_packets += received.sent;
    out.server_packets_missing += received.missing;
  }
  if (feed_) {
    const FeedCounts& counts = feed_->counts();
    out.snapshots += counts.snapshots;
    out.snapshots_refused += counts.snapshots_refused;
    out.bad_payloads += counts.bad_payloads;
    out.bad_events += counts.bad_events;
    out.snapshots_lost += feed_->gaps().lost();
  }
  if (rendered_) rendered_->add_to(out);
  if (game_) {
    const LinkCounters up = game_->link_up();
    const LinkCounters down = game_->link_down();
    out.sim_dropped += up.dropped + down.dropped;
    out.sim_duplicated += up.duplicated + down.duplicated;
    out.sim_reordered += up.reordered + down.reordered;
  }
}

BotMetrics Bot::metrics() const {
  BotMetrics out = metrics_;
  add_connection(out, steady_now_us());
  return out;
}

}  // namespace ricochet::bot
