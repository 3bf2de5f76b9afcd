#include "server.h"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/system/system_error.hpp>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <utility>
#include <variant>

#include "admin_advertisement.h"
#include "admin_http.h"
#include "agones_game_server.h"
#include "agones_http.h"
#include "chat_limiter.h"
#include "control_server.h"
#include "directory_heartbeat.h"
#include "episode_log.h"
#include "fleet_view.h"
#include "game_channel.h"
#include "map_view.h"
#include "match_defaults.h"
#include "match_registry.h"
#include "recording_files.h"
#include "results_outbox.h"
#include "ricochet/db/db_worker.h"
#include "ricochet/db/matches.h"
#include "ricochet/db/store.h"
#include "ricochet/proto/crypto.h"
#include "ricochet/proto/token_grant.h"
#include "ricochet/server/map.h"
#include "ricochet/server/rules.h"
#include "ricochet/wire/control.pb.h"
#include "steady_time.h"

namespace ricochet::server {

namespace {

namespace asio = boost::asio;
using Clock = std::chrono::steady_clock;

/// Recording bytes that may wait for the disk, all matches together, before the matches keep
/// their chunks in their writers (bounded by max_recording_bytes each): 2 048 chunks, over three
/// minutes of 16 matches of 16 at the measured 34 KB per player-minute (server/RECORDING.md).
constexpr std::size_t kMaxQueuedRecordingBytes = 32u << 20;

std::unique_ptr<db::DbWorker> open_database(const ServerConfig& config) {
  auto store = db::open_store(db::StoreOptions{.url_or_path = config.db_url_or_path()});
  if (!store) throw std::runtime_error("cannot open the database: " + store.error().message);
  db::DbWorkerOptions options;
  options.accounts.cost = config.db.password_hashing == PasswordHashing::Minimum
                              ? db::PasswordCost::Minimum
                              : db::PasswordCost::Interactive;
  if (options.accounts.cost == db::PasswordCost::Minimum) {
    spdlog::warn(
        "!!! db.password_hashing = \"minimum\": passwords are hashed with Argon2id's MINIMUM cost "
        "(8 KiB, 1 pass): a stolen database gives them up fast. For load tests only; never "
        "with real players' accounts. !!!");
  }
  options.accounts.registrations_per_address = {config.db.registrations_per_hour_per_address,
                                                3'600'000};
  options.password_nice = config.db.password_thread_nice;
  options.placement.server_ttl_ms = config.placement.server_ttl_s * 1000LL;
  options.placement.ticket_lifetime_ms = config.placement.ticket_lifetime_s * 1000LL;
  return std::make_unique<db::DbWorker>(std::move(store).value(), std::move(options));
}

Map load_map(const std::string& path) {
  auto loaded = load_map_file(path);
  if (auto* problem = std::get_if<MapError>(&loaded)) {
    throw std::runtime_error("cannot load the map " + path + ": " + problem->describe());
  }
  return std::get<Map>(std::move(loaded));
}

/// The limit a game-channel drop says an abuser ran into (logged once per episode), or null for
/// malformed and stray datagrams, which are only counted.
const char* exceeded_limit(proto::DropReason reason) {
  switch (reason) {
    case proto::DropReason::HalfOpenCap:
      return "game.max_half_open handshakes in progress";
    case proto::DropReason::HostHalfOpenCap:
      return "game.max_half_open_per_host handshakes in progress from one host";
    case proto::DropReason::HostFull:
      return "game.max_clients_per_host connections from one host";
    case proto::DropReason::AddressTableFull:
      return "game.max_tracked_addresses unconnected addresses";
    case proto::DropReason::UsedTokenTableFull:
      return "game.max_used_tokens connect tokens remembered";
    case proto::DropReason::AddressRateLimited:
      return "game.address_packets_per_s from an unconnected address";
    case proto::DropReason::ClientRateLimited:
      return "game.client_packets_per_s from a connected client";
    case proto::DropReason::HandshakeInProgress:
      return "a request for another account where a handshake is in progress";
    case proto::DropReason::TokenReused:
      return "a connect token that already opened a handshake";
    default:
      return nullptr;
  }
}

GameChannelConfig game_channel_config(const ServerConfig& config, EpisodeLog& episodes) {
  GameChannelConfig out;
  out.bind = config.game.bind;
  out.port = static_cast<std::uint16_t>(config.game.port);
  proto::GameServerConfig& transport = out.transport;
  transport.protocol_id = proto::kProtocolId;
  transport.max_clients = config.game.max_clients;
  transport.max_half_open = config.game.max_half_open;
  transport.address_packets_per_s = config.game.address_packets_per_s;
  transport.address_burst = config.game.address_packets_per_s;
  transport.client_packets_per_s = config.game.client_packets_per_s;
  transport.client_burst = config.game.client_packets_per_s;
  transport.max_half_open_per_host = config.game.max_half_open_per_host;
  transport.max_clients_per_host = config.game.max_clients_per_host;
  transport.max_tracked_addresses = config.game.max_tracked_addresses;
  transport.max_used_tokens = config.game.max_used_tokens;
  transport.log.on_transition = [](const proto::StateTransition& transition) {
    spdlog::debug("game channel: {} {} -> {} ({})", transition.address.to_string(),
                  proto::name(transition.from), proto::name(transition.to), transition.reason);
  };
  transport.log.on_drop = [&episodes](proto::DropReason reason, const proto::Address& from) {
    spdlog::debug("game channel: dropped a packet from {}: {}", from.to_string(),
                  proto::name(reason));
    if (const char* limit = exceeded_limit(reason)) {
      episodes.refuse(proto::name(reason), proto::host_key(from).to_string(), limit,
                      steady_now_us());
    }
  };
  return out;
}

ControlServerConfig control_config(const ServerConfig& config) {
  ControlServerConfig out;
  out.bind_address = config.control.bind;
  out.port = static_cast<std::uint16_t>(config.control.port);
  out.tls.certificate = config.tls.cert_file;
  out.tls.private_key = config.tls.key_file;
  out.tls.data_dir = config.server.data_dir;
  out.limits.max_connections = config.control.max_connections;
  out.limits.max_connections_per_address = config.control.max_connections_per_address;
  out.limits.handshake_timeout_ms = static_cast<std::uint32_t>(config.control.handshake_timeout_ms);
  out.limits.frame_timeout_ms = static_cast<std::uint32_t>(config.control.frame_timeout_ms);
  out.limits.idle_timeout_ms = static_cast<std::uint32_t>(config.control.idle_timeout_ms);
  out.limits.login_timeout_ms = static_cast<std::uint32_t>(config.control.login_timeout_ms);
  out.limits.messages_per_second = config.control.messages_per_second;
  out.limits.message_burst = config.control.message_burst;
  out.clock = steady_now_us;  // the match registry issues connect tokens on it too
  return out;
}

ChatLimits chat_limits(const ServerConfig& config) {
  ChatLimits out;
  out.account_lines_per_s = config.control.chat_account_lines_per_s;
  out.account_burst = config.control.chat_account_burst;
  out.match_lines_per_s = config.control.chat_match_lines_per_s;
  out.match_burst = config.control.chat_match_burst;
  return out;
}

/// Waits for `future` until `deadline`; false when it did not come in time.
template <class T>
bool wait_until(std::future<T>& future, Clock::time_point deadline) {
  return future.wait_until(deadline) == std::future_status::ready;
}

wire::Team wire_team(std::int32_t team) {
  switch (team) {
    case db::kTeamRed:
      return wire::TEAM_RED;
    case db::kTeamBlue:
      return wire::TEAM_BLUE;
    default:
      return wire::TEAM_NONE;
  }
}

/// Hit points are whole numbers; the store keeps them as reals.
std::int32_t hit_points(double value) {
  return static_cast<std::int32_t>(std::llround(value));
}

/// Creates `path` (and its parents) if missing, and makes it the owner's alone (0700): it holds
/// the TLS key and the database. A directory the server does not own is only warned about.
void make_private_directory(const std::string& path) {
  std::filesystem::create_directories(path);
  std::error_code error;
  std::filesystem::permissions(path, std::filesystem::perms::owner_all,
                               std::filesystem::perm_options::replace, error);
  if (error) {
    spdlog::warn("the data directory {} cannot be made private (mode 0700): {}", path,
                 error.message());
  }
}

/// The bearer token in `path` (surrounding whitespace dropped); throws when it is unreadable or
/// empty.
std::string read_admin_token(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw std::runtime_error("cannot read admin.token_file " + path);
  std::string token((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const auto first = token.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) {
    throw std::runtime_error("admin.token_file " + path + " is empty; write a token into it");
  }
  token = token.substr(first, token.find_last_not_of(" \t\r\n") - first + 1);
  return token;
}

SeatLimits seat_limits(const MatchesConfig& matches) {
  SeatLimits out;
  out.seats_per_address = matches.seats_per_address;
  out.reserved_seats_per_match = matches.reserved_seats_per_match;
  out.created_matches = matches.max_created;
  out.created_matches_per_account = matches.max_created_per_account;
  out.creates_per_minute = matches.creates_per_minute;
  out.creates_per_account_per_minute = matches.creates_per_account_per_minute;
  out.empty_match_close_after_us =
      static_cast<proto::TimeUs>(matches.empty_close_after_s * proto::kMicrosPerSecond);
  return out;
}

/// How often the created matches are looked at for being empty too long.
constexpr auto kEmptyMatchSweep = std::chrono::seconds(5);
/// How old a file of the outbox must be for a running server to take it as left by another
/// process (every db.outbox_rescan_s): a live writer removes its own within moments of the
/// database's commit, or retries it itself while the database is away, rewriting the file at
/// each attempt (at most Server::kRecordRetryLast apart: half this); a second delivery writes
/// nothing.
constexpr std::int64_t kLeftRecordAgeMs = 60'000;

}  // namespace

Server::Server(ServerConfig config) : config_(std::move(config)) {
  make_private_directory(config_.server.data_dir);
  db_ = open_database(config_);
  outbox_ = std::make_unique<ResultsOutbox>(config_.outbox_path());
  recordings_ =
      std::make_unique<RecordingFiles>(config_.recordings_path(), kMaxQueuedRecordingBytes);
  const proto::Key token_key = proto::random_key();  // this process's only; tokens die with it

  GameChannelConfig game = game_channel_config(config_, episodes_);
  game.transport.token_key = token_key;
  game_ = std::make_unique<GameChannel>(io_, std::move(game));

  chat_limiter_ = std::make_unique<ChatLimiter>(chat_limits(config_), episodes_);
  MatchRegistryConfig registry;
  registry.match_defaults = match_defaults(config_);
  registry.token_key = token_key;
  registry.chat_limiter = chat_limiter_.get();
  registry.token_reuse_us = config_.game.token_reuse_ms * proto::kMicrosPerMilli;
  registry.limits = seat_limits(config_.matches);
  registry.episodes = &episodes_;
  registry.recordings = recordings_.get();
  // Every map of the rotation is loaded now, so a broken one stops the start, not a match end.
  std::vector<Map> maps;
  for (const std::string& path : config_.matches.maps) maps.push_back(load_map(path));
  start_replays();
  for (const Map& map : maps) map_views_.try_emplace(map.name, web::map_view_json(map));
  matches_ = std::make_unique<MatchRegistry>(
      io_, std::move(registry), std::move(maps), *game_, [this](EndedMatch match) {
        if (agones_) agones_->match_finished();
        // The directory stops listing the ended match (and lists the next) sooner.
        if (heartbeat_) heartbeat_->matches_changed();
        finish_match(std::move(match), [this](std::optional<wire::MatchResults> results,
                                              const std::vector<std::uint64_t>& recipients) {
          if (results) send_results(*results, recipients);
        });
      });
  ControlServerConfig control = control_config(config_);
  control.episodes = &episodes_;
  if (config_.placement.on(config_.db)) {
    placement_.reset(new FleetPlacement{draw_server_id(),
                                        FindMatchLimiter(config_.placement.find_match_per_minute),
                                        placement_counters_, config_.matches.max_players, [this] {
                                          if (agones_)
                                            agones_->players_placed();  // made before any session
                                        }});
    control.placement = placement_.get();
  }
  control_ = std::make_unique<ControlServer>(io_, std::move(control), *db_, *matches_);

  AdminHttpOptions admin;
  admin.bind = config_.admin.bind;
  admin.port = static_cast<std::uint16_t>(config_.admin.port);
  admin.max_connections = config_.admin.max_connections;
  admin.max_connections_per_address = config_.admin.max_connections_per_address;
  admin.max_streams_per_address = config_.admin.max_streams_per_address;
  admin.max_signin_failures = config_.admin.signin_failures_per_minute;
  if (!config_.admin.token_file.empty()) {
    admin.bearer_token = read_admin_token(config_.admin.token_file);
  }
  admin.episodes = &episodes_;
  admin.files = dashboard_files();
  AdminHttpCallbacks callbacks{
      [this] { return healthy(); },
      [this] { return ready(); },
      [this](AccountAction action, std::function<void(AdminReply)> answer) {
        act_on_account(std::move(action), std::move(answer));
      },
      {}};  // /fleet: only with a directory row to show
  if (placement_) {
    callbacks.fleet = [this](std::function<void(AdminReply)> answer) {
      answer_fleet(std::move(answer));
    };
  }
  admin_ = std::make_unique<AdminHttp>(io_, std::move(admin), metrics_, std::move(callbacks));
  register_metrics();
  register_dashboard();
  register_replays();
  register_live();
  if (const char* sdk_port = std::getenv("AGONES_SDK_HTTP_PORT")) start_agones(sdk_port);
}

Server::~Server() {
  stop();
  wait();
}

void Server::start() {
  // A ports file left by an earlier run would name its ports until this one listens.
  if (const std::string ports_file = config_.ports_file_path(); !ports_file.empty()) {
    std::error_code ignored;
    std::filesystem::remove(ports_file, ignored);
  }
  try {
    game_->start(*matches_);
  } catch (const boost::system::system_error& error) {
    throw std::runtime_error("cannot bind the game channel (UDP) on " + config_.game.bind + ":" +
                             std::to_string(config_.game.port) + ": " + error.code().message());
  }
  matches_->set_udp_port(game_->port());
  for (int i = 1; i <= config_.matches.count; ++i) {
    std::string name = config_.matches.mode;  // "ffa-1", "tdm-1", ...
    name += '-';
    name += std::to_string(i);
    const auto opened = matches_->open(name, config_.matches.max_players);
    if (auto* problem = std::get_if<DirectoryError>(&opened)) {
      throw std::runtime_error("cannot open match " + std::to_string(i) + ": " + problem->message);
    }
  }
  try {
    control_->start();
  } catch (const boost::system::system_error& error) {
    throw std::runtime_error("cannot bind the control channel (TLS) on " + config_.control.bind +
                             ":" + std::to_string(config_.control.port) + ": " +
                             error.code().message());
  }
  if (const auto error = admin_->start()) {
    throw std::runtime_error("cannot bind the admin port " + config_.admin.bind + ":" +
                             std::to_string(config_.admin.port) + ": " + error.message());
  }
  write_ports_file();
  sweep_empty_matches();
  sample_overview();
  poll_live();
  if (placement_) start_placement();
  const int threads = config_.worker_threads();
  for (int i = 0; i < threads; ++i) threads_.emplace_back([this] { io_.run(); });
  deliver_outbox();
  rescan_outbox();
  ready_ = true;
  if (agones_) agones_->ready();
  spdlog::info(
      "ricochet-server {}: control TLS 1.3 on {}:{}, game UDP on {}:{}, admin HTTP on "
      "{}:{}, {} matches, {} threads",
      RICOCHET_VERSION, config_.control.bind, control_port(), config_.game.bind, game_port(),
      config_.admin.bind, admin_port(), config_.matches.count, threads);
  spdlog::info("TLS certificate SHA-256 fingerprint (pin it in clients): {}", fingerprint());
}

void Server::start_agones(const char* sdk_port) {
  AgonesHttpOptions options;
  options.port = parse_agones_sdk_port(sdk_port);
  options.sdk.shutdown_after_matches = config_.agones.shutdown_after_matches;
  options.matches = [this] {
    std::vector<AgonesMatchView> views;
    for (const auto& host : matches_->hosts()) {
      const MatchHostStats stats = host->stats();
      views.push_back(AgonesMatchView{.id = host->id(),
                                      .map = host->map_name(),
                                      .mode = name(host->mode()),
                                      .players = stats.seated,
                                      .capacity = host->max_players(),
                                      .last_tick_at = stats.last_tick_at,
                                      .overruns = stats.counters.overruns});
    }
    return views;
  };
  if (advertises_from_agones()) {
    agones_game_server_invalid_ = &metrics_.counter(
        "ricochet_agones_gameserver_invalid_total",
        "GET /gameserver answers refused or not a GameServer's address and ports (the configured "
        "ones advertised instead)");
    options.game_server = [this](std::optional<std::string> body) {
      boost::asio::post(io_, [this, body = std::move(body)] { advertise_from_agones(body); });
    };
  }
  agones_ = std::make_unique<AgonesHttp>(std::move(options), metrics_);
  spdlog::info("agones: the SDK sidecar's REST gateway is 127.0.0.1:{} (AGONES_SDK_HTTP_PORT)",
               sdk_port);
}

bool Server::advertises_from_agones() const {
  const PlacementConfig& placement = config_.placement;
  return std::getenv("AGONES_SDK_HTTP_PORT") != nullptr && placement.on(config_.db) &&
         (placement.advertise_host.empty() || placement.advertise_control_port == 0 ||
          placement.advertise_game_port == 0);
}

void Server::start_placement() {
  const PlacementConfig& placement = config_.placement;
  std::string host = placement.advertise_host;
  if (host.empty()) {
    std::array<char, 256> name{};
    if (gethostname(name.data(), name.size() - 1) == 0) host = name.data();
  }
  std::string fingerprint_hex;  // 64 lowercase hex digits, as the directory keeps it
  for (char c : fingerprint()) {
    if (c != ':') fingerprint_hex += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  db::GameServerRow& row = directory_row_;
  row.server_id = placement_->server_id;
  row.host = host;
  row.control_port =
      placement.advertise_control_port != 0 ? placement.advertise_control_port : control_port();
  row.game_port = placement.advertise_game_port != 0 ? placement.advertise_game_port : game_port();
  row.certificate_sha256 = fingerprint_hex;
  row.admin_port = advertised_admin_port(
      AdminAdvertisement{.bind = config_.admin.bind,
                         .bound_port = admin_port(),
                         .host = host,
                         .configured_port = placement.advertise_admin_port,
                         .agones = std::getenv("AGONES_SDK_HTTP_PORT") != nullptr});
  row.version = RICOCHET_VERSION;
  row.capacity = config_.game.max_clients;
  row.started_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                       std::chrono::system_clock::now().time_since_epoch())
                       .count();
  heartbeat_ = std::make_unique<DirectoryHeartbeat>(
      io_, *db_, *matches_, placement_counters_, placement.heartbeat_s * proto::kMicrosPerSecond,
      placement.server_ttl_s * proto::kMicrosPerSecond, [this] {
        DirectoryEntry entry{directory_row_, {}};
        // Before the players: claims_in_flight.h says why.
        entry.server.counted_ms = placement_->claims.counted_as_of();
        int players = 0;
        for (const MatchSummary& match : matches_->list()) {
          entry.matches.push_back(db::HostedMatch{.match_id = match.id,
                                                  .mode = match.mode,
                                                  .map = match.map,
                                                  .players = match.players,
                                                  .capacity = match.max_players,
                                                  .open = !stopping_.load()});
          players += match.players;
        }
        entry.server.players = std::min(players, entry.server.capacity);
        return entry;
      });
  if (agones_ && advertises_from_agones()) {
    // Under Agones the bound ports are the container's, not the host ports players reach.
    spdlog::info(
        "placement: server {} joins the fleet directory once the Agones sidecar says where "
        "players reach it (GET /gameserver)",
        row.server_id);
    return;
  }
  start_heartbeats();
}

void Server::advertise_from_agones(const std::optional<std::string>& body) {
  if (!heartbeat_ || stopping_) return;
  const PlacementConfig& placement = config_.placement;
  std::string refusal = "the sidecar refused GET /gameserver";
  if (body) {
    auto parsed = parse_game_server(*body);
    if (auto* address = std::get_if<AgonesAddress>(&parsed)) {
      if (placement.advertise_host.empty()) directory_row_.host = address->host;
      if (placement.advertise_control_port == 0)
        directory_row_.control_port = address->control_port;
      if (placement.advertise_game_port == 0) directory_row_.game_port = address->game_port;
      refusal.clear();
    } else {
      refusal = std::move(std::get<std::string>(parsed));
    }
  }
  if (!refusal.empty()) {
    agones_game_server_invalid_->inc();
    spdlog::error(
        "placement: {}; advertising the configured address instead (set [placement] "
        "advertise_host, advertise_control_port and advertise_game_port if it is not reachable)",
        refusal);
  }
  start_heartbeats();
}

void Server::start_heartbeats() {
  heartbeat_->start();
  spdlog::info(
      "placement: server {} advertises {}:{} (game port {}, admin port {}), heartbeat every {} s",
      directory_row_.server_id, directory_row_.host, directory_row_.control_port,
      directory_row_.game_port,
      directory_row_.admin_port != 0 ? std::to_string(directory_row_.admin_port) : "none",
      config_.placement.heartbeat_s);
}

void Server::sweep_empty_matches() {
  empty_match_sweep_.expires_after(kEmptyMatchSweep);
  empty_match_sweep_.async_wait([this](const boost::system::error_code& error) {
    if (error || !ready_) return;  // cancelled, or stopping
    matches_->close_empty_matches();
    sweep_empty_matches();
  });
}

void Server::write_ports_file() const {
  const std::string path = config_.ports_file_path();
  if (path.empty()) return;
  // Written beside and renamed into place, so a reader never sees half a line.
  const std::string partial = path + ".partial";
  {
    std::ofstream file(partial, std::ios::trunc);
    file << "{\"control_port\":" << control_port() << ",\"game_port\":" << game_port()
         << ",\"admin_port\":" << admin_port() << ",\"fingerprint\":\"" << fingerprint()
         << "\",\"pid\":" << getpid() << "}\n";
    file.close();
    if (!file) throw std::runtime_error("cannot write the ports file " + partial);
  }
  std::error_code error;
  std::filesystem::rename(partial, path, error);
  if (error) {
    throw std::runtime_error("cannot rename " + partial + " to " + path + ": " + error.message());
  }
}

void Server::stop() {
  std::call_once(stop_once_, [this] {
    const std::lock_guard lock(done_mutex_);  // wait() reads stopper_ under it
    stopper_ = std::thread([this] { shut_down(); });
  });
}

int Server::wait() {
  std::unique_lock lock(done_mutex_);
  done_.wait(lock, [this] { return stopped_; });
  // shut_down() released the lock after its last step, so its thread is ending.
  if (stopper_.joinable() && stopper_.get_id() != std::this_thread::get_id()) stopper_.join();
  return exit_code_.load();
}

std::uint16_t Server::control_port() const {
  return control_->port();
}
std::uint16_t Server::game_port() const {
  return game_->port();
}
std::uint16_t Server::admin_port() const {
  return admin_->local_endpoint().port();
}
const std::string& Server::fingerprint() const {
  return control_->identity().fingerprint_sha256;
}

bool Server::healthy() const {
  const proto::TimeUs now = steady_now_us();
  for (const auto& host : matches_->hosts()) {
    if (now - host->stats().last_tick_at > proto::kMicrosPerSecond) return false;
  }
  return ready_.load();
}

void Server::shut_down() {
  if (threads_.empty()) {
    // start() never ran its threads (it failed, or was never called): nothing to end or tell.
    db_->stop();
    exit_code_ = 1;
    const std::lock_guard lock(done_mutex_);
    stopped_ = true;
    done_.notify_all();
    return;
  }
  stopping_ = true;
  if (const std::uint64_t pending = records_pending_.load()) {
    spdlog::error(
        "stopping: {} match records still could not be written; they stay in the results outbox "
        "{} and are written at the next start",
        pending, outbox_->directory().string());
  }
  const auto deadline = Clock::now() + std::chrono::seconds(config_.server.shutdown_grace_s);
  spdlog::info("stopping: ending {} matches, {} s grace", matches_->hosts().size(),
               config_.server.shutdown_grace_s);
  ready_ = false;
  if (agones_) agones_->stopping();
  // Out of the fleet directory first: no player is placed here while the matches end.
  if (heartbeat_ && !heartbeat_->leave(std::chrono::seconds(2))) {
    spdlog::warn("stopping: the directory row was not deleted; it goes stale in {} s",
                 config_.placement.server_ttl_s);
  }
  matches_->close();  // no joins, no new game connections into a match
  // The DB writes get the grace less 2 s (at least half of it), so that telling the game and
  // control clients always has time left.
  const auto grace = std::chrono::seconds(config_.server.shutdown_grace_s);
  end_matches(std::max(deadline - std::chrono::seconds(2), Clock::now() + grace / 2));

  std::promise<void> game_closed;
  auto game_closed_future = game_closed.get_future();
  game_->stop([&game_closed] { game_closed.set_value(); });
  const bool game_done = wait_until(game_closed_future, deadline);
  control_->stop();
  admin_->stop();
  // The control sessions say SHUTTING_DOWN and close within 2 s; then nothing is left to run.
  while (control_->connections() > 0 && Clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  const bool in_time = game_done && Clock::now() < deadline;
  io_.stop();
  for (auto& thread : threads_) thread.join();
  threads_.clear();
  replay_routes_.reset();
  replays_.reset();     // no route can reach the pool now: its workers stop and are joined
  recordings_->stop();  // every match has handed its recording over by now
  db_->stop();
  if (!in_time) spdlog::warn("stopping: the grace period ran out");
  // Drained: Agones may delete the pod now. Within the signals' backstop (the grace and 2 s).
  const auto shutdown_wait = std::chrono::duration_cast<std::chrono::milliseconds>(
      deadline + std::chrono::seconds(1) - Clock::now());
  if (agones_ && !agones_->drained(std::clamp(shutdown_wait, std::chrono::milliseconds(200),
                                              std::chrono::milliseconds(2000)))) {
    spdlog::warn("agones: POST /shutdown was not answered; Agones ends the pod on its own");
  }
  spdlog::info("stopped");
  exit_code_ = in_time ? 0 : 1;
  const std::lock_guard lock(done_mutex_);
  stopped_ = true;
  done_.notify_all();
}

void Server::end_matches(Clock::time_point deadline) {
  // Each match hands over its record on its own strand.
  std::vector<std::future<EndedMatch>> ended;
  for (const auto& host : matches_->hosts()) {
    auto promise = std::make_shared<std::promise<EndedMatch>>();
    ended.push_back(promise->get_future());
    host->end([promise](EndedMatch match) { promise->set_value(std::move(match)); });
  }
  struct Written {
    std::optional<wire::MatchResults> results;
    std::vector<std::uint64_t> recipients;
  };
  std::vector<std::future<Written>> written;
  for (auto& future : ended) {
    if (!wait_until(future, deadline)) {
      spdlog::warn("stopping: a match did not hand over its record in time; it is not written");
      continue;
    }
    auto promise = std::make_shared<std::promise<Written>>();
    written.push_back(promise->get_future());
    finish_match(future.get(), [promise](std::optional<wire::MatchResults> results,
                                         const std::vector<std::uint64_t>& recipients) {
      promise->set_value(Written{std::move(results), recipients});
    });
  }
  // Every player hears its results over the control channel before it closes.
  for (auto& future : written) {
    if (!wait_until(future, deadline)) {
      spdlog::warn("stopping: a match record was not written in time; its players get no results");
      continue;
    }
    const Written done = future.get();
    if (done.results) send_results(*done.results, done.recipients);
  }
}

void Server::finish_match(EndedMatch match, ResultsHandler done) {
  if (!match.recording.empty()) {
    recordings_->finish(RecordingFiles::part_name(match.id, match.record.started_ms),
                        RecordingFiles::file_name(match.id, match.record.ended_ms),
                        std::move(match.recording));
  }
  if (match.record.players.empty()) {
    // Nobody played (those seated only waited for opponents): nothing to record, but whoever
    // was seated hears that the match is over.
    if (match.seated.empty()) {
      done(std::nullopt, {});
      return;
    }
    done(results_header(match), match.seated);
    return;
  }
  match.recording.clear();
  match.record.uuid = db::new_match_uuid();
  write_record(std::make_shared<const EndedMatch>(std::move(match)), 1, std::move(done));
}

void Server::deliver_outbox() {
  std::vector<OutboxRecord> left = outbox_->list();
  if (left.empty()) return;
  spdlog::warn("results outbox: {} match records left by an earlier process; writing them",
               left.size());
  deliver(std::move(left));
}

void Server::rescan_outbox() {
  outbox_rescan_.expires_after(std::chrono::seconds(config_.db.outbox_rescan_s));
  outbox_rescan_.async_wait([this](const boost::system::error_code& error) {
    if (error || !ready_) return;  // cancelled, or stopping
    const db::UnixMillis now = std::chrono::duration_cast<std::chrono::milliseconds>(
                                   std::chrono::system_clock::now().time_since_epoch())
                                   .count();
    std::vector<OutboxRecord> left = outbox_->list_left(now, kLeftRecordAgeMs);
    if (!left.empty()) {
      spdlog::warn(
          "results outbox: {} match records left by another process (older than {} s); "
          "writing them",
          left.size(), kLeftRecordAgeMs / 1000);
      deliver(std::move(left));
    }
    rescan_outbox();
  });
}

void Server::deliver(std::vector<OutboxRecord> left) {
  for (OutboxRecord& kept : left) {
    EndedMatch match;
    match.id = kept.match_id;
    match.usernames.resize(kept.record.players.size());  // nobody to tell: no names needed
    match.record = std::move(kept.record);
    write_record(
        std::make_shared<const EndedMatch>(std::move(match)), 1,
        [](std::optional<wire::MatchResults>, const std::vector<std::uint64_t>&) {}, true);
  }
}

namespace {

/// A write that failed for a reason that can pass (a full disk, a lock held by another
/// process, the database server away, a queue or memory running out): the record is kept and
/// written again.
bool worth_retrying(db::DbErrorCode code) {
  switch (code) {
    case db::DbErrorCode::Storage:
    case db::DbErrorCode::Busy:
    case db::DbErrorCode::Unavailable:
    case db::DbErrorCode::QueueFull:
    case db::DbErrorCode::OutOfMemory:
      return true;
    default:
      return false;
  }
}

}  // namespace

void Server::write_record(std::shared_ptr<const EndedMatch> match, int attempt, ResultsHandler done,
                          bool from_outbox) {
  db_->submit(
      [this, match, from_outbox](db::DbServices& services) {
        // Journalled before the attempt (results_outbox.h): from here on a kill -9 loses nothing.
        // On the DB thread, as its fsyncs must not stall a tick; again at each attempt, in case
        // the first never ran (a full queue), rewriting the same bytes.
        if (!from_outbox) outbox_->keep(OutboxRecord{match->id, match->record});
        return record(*match, services);
      },
      [](std::function<void()> completion) { completion(); },  // runs on the DB thread
      [this, match, attempt, from_outbox,
       done = std::move(done)](db::DbResult<wire::MatchResults> result) {
        const std::string& uuid = match->record.uuid;
        if (result) {
          outbox_->remove(uuid);
          if (from_outbox) outbox_delivered_.fetch_add(1);
          if (attempt > 1) {
            spdlog::info("match {}: its record was written at attempt {}", match->id, attempt);
            records_pending_.fetch_sub(1);
          }
          if (done) done(std::move(result).value(), match->seated);
          return;
        }
        const db::DbError& error = result.error();
        if (!worth_retrying(error.code)) {
          spdlog::error("match {} ({}): its record was refused: {}", match->id, uuid,
                        error.message);
          outbox_->remove(uuid);
          if (attempt > 1) records_pending_.fetch_sub(1);
          records_lost_.fetch_add(1);
          if (done) done(std::nullopt, match->seated);
          return;
        }
        // The players hear at once what is known; their ratings come with the record.
        if (done) done(pending_results(*match), match->seated);
        if (stopping_.load()) {
          spdlog::error(
              "match {} ({}): its record could not be written while stopping ({}: {}); it stays "
              "in the results outbox for the next start",
              match->id, uuid, db::to_string(error.code), error.message);
          if (attempt > 1) records_pending_.fetch_sub(1);
          return;
        }
        if (attempt == 1) records_pending_.fetch_add(1);
        records_retried_.fetch_add(1);
        const std::chrono::seconds wait =
            std::min(kRecordRetryFirst * (1 << std::min(attempt - 1, 5)), kRecordRetryLast);
        spdlog::error(
            "match {} ({}): its record could not be written ({}: {}); kept, attempt {} in {} s",
            match->id, uuid, db::to_string(error.code), error.message, attempt + 1, wait.count());
        auto timer = std::make_shared<asio::steady_timer>(io_, wait);
        timer->async_wait([this, timer, match, attempt, from_outbox](const std::error_code&) {
          write_record(match, attempt + 1, nullptr, from_outbox);
        });
      });
}

void Server::answer_fleet(std::function<void(AdminReply)> answer) {
  const auto unix_now_ms = [] {
    return std::chrono::duration_cast<std::chrono::milliseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
  };
  db_->submit(
      [now = unix_now_ms()](db::DbServices& services) { return services.placement.directory(now); },
      [](std::function<void()> completion) { completion(); },  // runs on the DB thread
      [this, unix_now_ms, answer = std::move(answer)](db::DbResult<db::FleetDirectory> result) {
        if (!result) {
          spdlog::debug("admin: /fleet: the directory could not be read: {}",
                        result.error().message);
          answer({503, std::string("the database could not answer now (") +
                           db::to_string(result.error().code) + "); try again\n"});
          return;
        }
        answer({200, fleet_json(result.value(), placement_->server_id, unix_now_ms()),
                "application/json"});
      });
}

void Server::act_on_account(AccountAction action, std::function<void(AdminReply)> answer) {
  const bool ban = action.ban;
  const std::string username = action.username;
  db_->submit(
      [username, ban](db::DbServices& services) {
        return services.accounts.set_banned_by_name(username, ban);
      },
      [](std::function<void()> completion) { completion(); },  // runs on the DB thread
      [this, action = std::move(action),
       answer = std::move(answer)](db::DbResult<db::Account> result) {
        if (!result) {
          const db::DbError& error = result.error();
          if (error.code == db::DbErrorCode::UnknownAccount) {
            answer({404, error.message + "\n"});
            return;
          }
          spdlog::error("admin {}: {} of '{}' failed: {}", action.operator_address,
                        action.ban ? "the ban" : "the unban", action.username, error.message);
          answer({503, std::string("the database could not take it now (") +
                           db::to_string(error.code) + "); try again\n"});
          return;
        }
        const db::Account account = std::move(result).value();
        const auto id = static_cast<std::uint64_t>(account.id);
        if (!action.ban) {
          control_->unban_account(id);
          unbans_.fetch_add(1);
          spdlog::warn("admin {}: account '{}' ({}) unbanned", action.operator_address,
                       account.username, id);
          answer(
              {200, "account '" + account.username + "' (" + std::to_string(id) + ") unbanned\n"});
          return;
        }
        // Closing the sessions and taking the seat happen on the control strand in one go, so
        // no session of the account can join a match in between.
        control_->ban_account(
            id, "account '" + account.username + "' is banned",
            [this, id, account, action, answer](std::size_t closed) {
              const bool removed = matches_->remove(id, proto::DisconnectReason::Banned);
              bans_.fetch_add(1);
              banned_sessions_closed_.fetch_add(closed);
              banned_players_removed_.fetch_add(removed ? 1 : 0);
              const std::string done = "account '" + account.username + "' (" + std::to_string(id) +
                                       ") banned: its sessions revoked, " + std::to_string(closed) +
                                       " control connections closed, " +
                                       (removed ? "taken out of its match" : "in no match");
              spdlog::warn("admin {}: {}", action.operator_address, done);
              answer({200, done + "\n"});
            });
      });
}

void Server::send_results(const wire::MatchResults& results,
                          const std::vector<std::uint64_t>& recipients) {
  // The players in the record (some may have left before the end) and everyone still seated.
  std::vector<std::uint64_t> accounts = recipients;
  for (const wire::PlayerMatchResult& player : results.players()) {
    accounts.push_back(player.account_id());
  }
  std::sort(accounts.begin(), accounts.end());
  accounts.erase(std::unique(accounts.begin(), accounts.end()), accounts.end());
  for (const std::uint64_t account : accounts) {
    wire::ServerMessage message;
    *message.mutable_match_results() = results;
    control_->send_to_account(account, std::move(message));
  }
}

wire::MatchResults Server::results_header(const EndedMatch& match) {
  const db::MatchRecord& record = match.record;
  wire::MatchResults results;
  results.set_match_id(match.id);
  results.set_map(record.map);
  results.set_mode(record.mode);
  results.set_aborted(record.aborted);
  results.set_end_reason(match.end_reason);
  if (record.mode == db::kModeTeamDeathmatch) {
    for (const auto& [team, score] : {std::pair{wire::TEAM_RED, record.team_scores.red},
                                      std::pair{wire::TEAM_BLUE, record.team_scores.blue}}) {
      wire::TeamScore& out = *results.add_team_scores();
      out.set_team(team);
      out.set_score(score);
    }
  }
  return results;
}

wire::MatchResults Server::pending_results(const EndedMatch& match) {
  wire::MatchResults results = results_header(match);
  results.set_record_pending(true);
  const db::MatchRecord& record = match.record;
  for (std::size_t i = 0; i < record.players.size(); ++i) {
    const db::PlayerResult& player = record.players[i];
    wire::PlayerMatchResult& out = *results.add_players();
    out.set_account_id(static_cast<std::uint64_t>(player.account));
    out.set_username(match.usernames[i]);
    out.set_team(wire_team(player.team));
    out.set_kills(player.kills);
    out.set_deaths(player.deaths);
    out.set_score(player.score);
    out.set_shots(player.shots);
    out.set_hits(player.hits);
    out.set_damage_dealt(hit_points(player.damage_dealt));
    out.set_damage_taken(hit_points(player.damage_taken));
    out.set_seconds_played(player.seconds_played);
  }
  return results;
}

db::DbResult<wire::MatchResults> Server::record(const EndedMatch& match, db::DbServices& services) {
  const db::MatchRecord& record = match.record;
  auto recorded = services.matches.record_match(record);
  if (!recorded) return recorded.error();
  const std::vector<db::PlayerOutcome>& outcomes = recorded.value().outcomes;
  spdlog::info("match {} ({}) recorded as {} ({} players, {}{}{})", match.id, record.uuid,
               recorded.value().id, record.players.size(), record.mode,
               record.aborted ? ", aborted" : "",
               recorded.value().existed ? "; it was already: nothing written again" : "");
  wire::MatchResults results = pending_results(match);
  results.clear_record_pending();
  for (std::size_t i = 0; i < record.players.size(); ++i) {
    auto rank = services.matches.rank_of(record.players[i].account, db::LeaderboardKind::Rating);
    if (!rank) return rank.error();
    wire::PlayerMatchResult& out = *results.mutable_players(static_cast<int>(i));
    out.set_won(outcomes[i].won);
    out.set_rating_before(outcomes[i].rating_before);
    out.set_rating_after(outcomes[i].rating_after);
    // Every player of a recorded match is on the rating board.
    if (rank.value()) out.set_rank(static_cast<std::uint32_t>(rank.value()->rank));
  }
  return results;
}

}  // namespace ricochet::server
