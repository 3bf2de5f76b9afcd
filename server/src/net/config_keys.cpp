#include "config_keys.h"

#include <array>
#include <boost/asio/ip/address.hpp>
#include <charconv>
#include <cmath>
#include <limits>

#include "replay_jobs.h"

namespace ricochet::server {

const char* name(LogLevel level) {
  switch (level) {
    case LogLevel::Trace:
      return "trace";
    case LogLevel::Debug:
      return "debug";
    case LogLevel::Info:
      return "info";
    case LogLevel::Warn:
      return "warn";
    case LogLevel::Error:
      return "error";
    case LogLevel::Critical:
      return "critical";
    case LogLevel::Off:
      return "off";
  }
  return "unknown";
}

const char* name(PasswordHashing hashing) {
  switch (hashing) {
    case PasswordHashing::Interactive:
      return "interactive";
    case PasswordHashing::Minimum:
      return "minimum";
  }
  return "unknown";
}

const char* name(PlacementMode mode) {
  switch (mode) {
    case PlacementMode::Auto:
      return "auto";
    case PlacementMode::On:
      return "on";
    case PlacementMode::Off:
      return "off";
  }
  return "unknown";
}

const char* name(LogFormat format) {
  switch (format) {
    case LogFormat::Text:
      return "text";
    case LogFormat::Json:
      return "json";
  }
  return "unknown";
}

namespace config_keys {
namespace {

template <auto Section, auto Member>
int& integer_of(ServerConfig& config) {
  return (config.*Section).*Member;
}

template <auto Section, auto Member>
std::string& text_of(ServerConfig& config) {
  return (config.*Section).*Member;
}

template <auto Section, auto Member>
double& number_of(ServerConfig& config) {
  return (config.*Section).*Member;
}

template <auto Section, auto Member>
bool& boolean_of(ServerConfig& config) {
  return (config.*Section).*Member;
}

template <auto Section, auto Member>
std::vector<std::string>& texts_of(ServerConfig& config) {
  return (config.*Section).*Member;
}

/// The shortest text that reads back as exactly `value`; "10", "1.5", "1e-05".
std::string number_text(double value) {
  std::array<char, 32> buffer{};
  const auto [end, error] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  if (error != std::errc{}) return "nan";
  return std::string(buffer.data(), end);
}

/// Writes a TOML basic string: quotes, backslashes and control characters escaped.
std::string toml_quote(std::string_view text) {
  std::string quoted = "\"";
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      quoted += '\\';
      quoted += c;
    } else if (byte < 0x20 || byte == 0x7f) {
      static constexpr char kHex[] = "0123456789abcdef";
      quoted += "\\u00";
      quoted += kHex[byte >> 4];
      quoted += kHex[byte & 0xf];
    } else {
      quoted += c;
    }
  }
  return quoted + '"';
}

/// Sets `out` to the enumerator whose name() is `text`.
template <class Enum, std::size_t N>
bool parse_enum(const std::array<Enum, N>& values, std::string_view text, Enum& out) {
  for (Enum value : values) {
    if (text == name(value)) {
      out = value;
      return true;
    }
  }
  return false;
}

constexpr std::array kLogLevels = {LogLevel::Trace, LogLevel::Debug, LogLevel::Info,
                                   LogLevel::Warn,  LogLevel::Error, LogLevel::Critical,
                                   LogLevel::Off};
constexpr std::array kLogFormats = {LogFormat::Text, LogFormat::Json};
constexpr std::array kPlacementModes = {PlacementMode::Auto, PlacementMode::On, PlacementMode::Off};
constexpr std::array kPasswordHashings = {PasswordHashing::Interactive, PasswordHashing::Minimum};

using S = ServerConfig;
// The [dashboard] defaults are the match's live feed defaults, and its ranges LiveFeedConfig's.
static_assert(DashboardConfig{}.live_feed_hz == LiveFeedConfig{}.rate_hz);
static_assert(DashboardConfig{}.live_feed_max_viewers == LiveFeedConfig{}.max_viewers);
constexpr int kMaxPort = 65535;

const std::array kKeys = {
    Key{.section = "server",
        .name = "data_dir",
        .flag = "--data-dir",
        .help = "directory of the database and the generated TLS pair; created if missing",
        .kind = Kind::Text,
        .text = &text_of<&S::server, &ProcessConfig::data_dir>},
    Key{.section = "server",
        .name = "threads",
        .flag = "--threads",
        .help = "match worker threads; 0: one per core",
        .integer = &integer_of<&S::server, &ProcessConfig::threads>,
        .min = 0,
        .max = 256},
    Key{.section = "server",
        .name = "shutdown_grace_s",
        .flag = "--shutdown-grace-s",
        .help = "seconds after SIGINT/SIGTERM to end matches and flush results before exiting",
        .integer = &integer_of<&S::server, &ProcessConfig::shutdown_grace_s>,
        .min = 1,
        .max = 300},
    Key{.section = "server",
        .name = "ports_file",
        .flag = "--ports-file",
        .help = "file written once listening: the bound ports, certificate fingerprint and pid as "
                "one JSON line; a relative path is under server.data_dir; empty: none",
        .kind = Kind::Text,
        .text = &text_of<&S::server, &ProcessConfig::ports_file>,
        .allow_empty = true},
    Key{.section = "db",
        .name = "path",
        .flag = "--db-path",
        .help = "SQLite database file; a relative path is under server.data_dir",
        .kind = Kind::Text,
        .text = &text_of<&S::db, &DbConfig::path>},
    Key{.section = "db",
        .name = "url",
        .flag = "--db-url",
        .help = "PostgreSQL database shared by many servers, postgresql://user@host:port/dbname "
                "(the password in the URL, or from PGPASSWORD or ~/.pgpass); empty: the SQLite "
                "file db.path",
        .kind = Kind::Text,
        .text = &text_of<&S::db, &DbConfig::url>,
        .allow_empty = true},
    Key{.section = "db",
        .name = "outbox_dir",
        .flag = "--outbox-dir",
        .help = "directory where each ended match's result is kept until the database has it "
                "(it outlives the database being away and the server being killed); a relative "
                "path is under server.data_dir",
        .kind = Kind::Text,
        .text = &text_of<&S::db, &DbConfig::outbox_dir>},
    Key{.section = "db",
        .name = "outbox_rescan_s",
        .flag = "--outbox-rescan-s",
        .help = "seconds between two looks of a running server for the results other servers "
                "left in a shared outbox_dir (killed, or their database away for long); it "
                "takes only those whose file is over 60 s old",
        .integer = &integer_of<&S::db, &DbConfig::outbox_rescan_s>,
        .min = 1,
        .max = 3600},
    Key{.section = "db",
        .name = "password_hashing",
        .flag = "--password-hashing",
        .help = "Argon2id cost of each password hash: interactive (64 MiB, ~100 ms; keep it for "
                "real accounts) or minimum (load tests only: thousands of bots signing in)",
        .kind = Kind::Choice,
        .choices = "interactive|minimum",
        .get_choice = [](const ServerConfig& c) -> std::string_view {
          return name(c.db.password_hashing);
        },
        .set_choice =
            [](ServerConfig& c, std::string_view text) {
              return parse_enum(kPasswordHashings, text, c.db.password_hashing);
            }},
    // --- abuse limits of accounts (issue 29) ---
    Key{.section = "db",
        .name = "registrations_per_hour_per_address",
        .flag = "--registrations-per-hour-per-address",
        .help = "accounts registered from one address (IPv4, or IPv6 /64) in an hour, counted in "
                "the database so every server process on it shares the limit",
        .integer = &integer_of<&S::db, &DbConfig::registrations_per_hour_per_address>,
        .min = 1,
        .max = 1'000'000},
    Key{.section = "db",
        .name = "password_thread_nice",
        .flag = "--password-thread-nice",
        .help = "nice value of the Argon2id password threads (19: lowest priority): a sign-in "
                "storm takes the cores the match ticks leave; 10 gives a hash about a tenth of a "
                "core a tick also wants",
        .integer = &integer_of<&S::db, &DbConfig::password_thread_nice>,
        .min = 0,
        .max = 19},
    Key{.section = "tls",
        .name = "cert_file",
        .flag = "--tls-cert",
        .help = "PEM certificate chain; empty (with key_file empty): a self-signed pair is "
                "generated in server.data_dir",
        .kind = Kind::Text,
        .text = &text_of<&S::tls, &TlsConfig::cert_file>,
        .allow_empty = true},
    Key{.section = "tls",
        .name = "key_file",
        .flag = "--tls-key",
        .help = "PEM private key of cert_file; set both or neither",
        .kind = Kind::Text,
        .text = &text_of<&S::tls, &TlsConfig::key_file>,
        .allow_empty = true},
    Key{.section = "control",
        .name = "bind",
        .flag = "--control-bind",
        .help = "address of the TLS control channel (TCP)",
        .kind = Kind::Address,
        .text = &text_of<&S::control, &ControlConfig::bind>},
    Key{.section = "control",
        .name = "port",
        .flag = "--control-port",
        .help = "TCP port of the control channel; 0: any free port",
        .integer = &integer_of<&S::control, &ControlConfig::port>,
        .min = 0,
        .max = kMaxPort},
    Key{.section = "control",
        .name = "max_connections",
        .flag = "--max-connections",
        .help = "control connections, all addresses together",
        .integer = &integer_of<&S::control, &ControlConfig::max_connections>,
        .min = 1,
        .max = 1'000'000},
    Key{.section = "control",
        .name = "max_connections_per_address",
        .flag = "--max-connections-per-address",
        .help = "control connections from one IP address; at most max_connections",
        .integer = &integer_of<&S::control, &ControlConfig::max_connections_per_address>,
        .min = 1,
        .max = 1'000'000},
    Key{.section = "control",
        .name = "handshake_timeout_ms",
        .flag = "--handshake-timeout-ms",
        .help = "milliseconds from accept to a finished TLS handshake",
        .integer = &integer_of<&S::control, &ControlConfig::handshake_timeout_ms>,
        .min = 100,
        .max = 60'000},
    Key{.section = "control",
        .name = "frame_timeout_ms",
        .flag = "--frame-timeout-ms",
        .help = "milliseconds from the first byte of a frame to its last (slowloris)",
        .integer = &integer_of<&S::control, &ControlConfig::frame_timeout_ms>,
        .min = 100,
        .max = 600'000},
    Key{.section = "control",
        .name = "idle_timeout_ms",
        .flag = "--idle-timeout-ms",
        .help = "milliseconds without a whole frame before a connection is closed",
        .integer = &integer_of<&S::control, &ControlConfig::idle_timeout_ms>,
        .min = 1'000,
        .max = 3'600'000},
    Key{.section = "control",
        .name = "login_timeout_ms",
        .flag = "--login-timeout-ms",
        .help = "milliseconds from the TLS handshake to a login or resume before a connection is "
                "closed (pings do not extend it)",
        .integer = &integer_of<&S::control, &ControlConfig::login_timeout_ms>,
        .min = 1'000,
        .max = 3'600'000},
    Key{.section = "control",
        .name = "messages_per_second",
        .flag = "--control-messages-per-second",
        .help = "requests per second one control connection may send, sustained",
        .integer = &integer_of<&S::control, &ControlConfig::messages_per_second>,
        .min = 1,
        .max = 10'000},
    Key{.section = "control",
        .name = "message_burst",
        .flag = "--control-message-burst",
        .help = "requests one control connection may send at once",
        .integer = &integer_of<&S::control, &ControlConfig::message_burst>,
        .min = 1,
        .max = 100'000},
    // Chat limits (ChatLimiter), per account across its sessions and per match.
    Key{.section = "control",
        .name = "chat_account_lines_per_s",
        .flag = "--chat-account-lines-per-s",
        .help = "chat lines per second one account may send, sustained, all its sessions together",
        .kind = Kind::Number,
        .number = &number_of<&S::control, &ControlConfig::chat_account_lines_per_s>,
        .min_number = 0.01,
        .max_number = 100},
    Key{.section = "control",
        .name = "chat_account_burst",
        .flag = "--chat-account-burst",
        .help = "chat lines one account may send at once",
        .integer = &integer_of<&S::control, &ControlConfig::chat_account_burst>,
        .min = 1,
        .max = 1'000},
    Key{.section = "control",
        .name = "chat_match_lines_per_s",
        .flag = "--chat-match-lines-per-s",
        .help = "chat lines per second one match carries, sustained, all its players together",
        .kind = Kind::Number,
        .number = &number_of<&S::control, &ControlConfig::chat_match_lines_per_s>,
        .min_number = 0.01,
        .max_number = 1'000},
    Key{.section = "control",
        .name = "chat_match_burst",
        .flag = "--chat-match-burst",
        .help = "chat lines one match may carry at once",
        .integer = &integer_of<&S::control, &ControlConfig::chat_match_burst>,
        .min = 1,
        .max = 1'000},
    Key{.section = "game",
        .name = "bind",
        .flag = "--game-bind",
        .help = "address of the encrypted game channel (UDP)",
        .kind = Kind::Address,
        .text = &text_of<&S::game, &GameConfig::bind>},
    Key{.section = "game",
        .name = "port",
        .flag = "--game-port",
        .help = "UDP port of the game channel; 0: any free port",
        .integer = &integer_of<&S::game, &GameConfig::port>,
        .min = 0,
        .max = kMaxPort},
    Key{.section = "game",
        .name = "tick_rate_hz",
        .flag = "--tick-rate-hz",
        .help = "fixed simulation steps per second of every match",
        .integer = &integer_of<&S::game, &GameConfig::tick_rate_hz>,
        .min = 10,
        .max = 128},
    Key{.section = "game",
        .name = "snapshot_rate_hz",
        .flag = "--snapshot-rate-hz",
        .help = "snapshots per second to each client; 0: the tick rate; at most tick_rate_hz",
        .integer = &integer_of<&S::game, &GameConfig::snapshot_rate_hz>,
        .min = 0,
        .max = 128},
    Key{.section = "game",
        .name = "max_catch_up_steps",
        .flag = "--max-catch-up-steps",
        .help = "fixed steps one tick may run to catch up after a stall (the rest is dropped "
                "and counted as an overrun)",
        .integer = &integer_of<&S::game, &GameConfig::max_catch_up_steps>,
        .min = 1,
        .max = 64},
    Key{.section = "game",
        .name = "max_clients",
        .flag = "--max-clients",
        .help = "connected game clients, all matches together (one core held 800 to 1450 bots "
                "in tools/bench/CAPACITY.md)",
        .integer = &integer_of<&S::game, &GameConfig::max_clients>,
        .min = 1,
        .max = 4096},
    Key{.section = "game",
        .name = "max_half_open",
        .flag = "--max-half-open",
        .help = "game handshakes in progress at once (challenged, not yet connected)",
        .integer = &integer_of<&S::game, &GameConfig::max_half_open>,
        .min = 1,
        .max = 65'536},
    Key{.section = "game",
        .name = "address_packets_per_s",
        .flag = "--address-packets-per-s",
        .help = "datagrams per second accepted from an unconnected address; the rest are "
                "dropped and counted",
        .integer = &integer_of<&S::game, &GameConfig::address_packets_per_s>,
        .min = 1,
        .max = 1'000'000},
    Key{.section = "game",
        .name = "client_packets_per_s",
        .flag = "--client-packets-per-s",
        .help = "datagrams per second accepted from a connected client; the rest are dropped "
                "and counted",
        .integer = &integer_of<&S::game, &GameConfig::client_packets_per_s>,
        .min = 1,
        .max = 1'000'000},
    Key{.section = "game",
        .name = "bandwidth_kbps_per_client",
        .flag = "--bandwidth-kbps",
        .help = "snapshot bandwidth budget per client, kilobits per second (one snapshot gets "
                "at most 1100 bytes, at least 128)",
        .integer = &integer_of<&S::game, &GameConfig::bandwidth_kbps_per_client>,
        .min = 16,
        .max = 100'000},
    Key{.section = "game",
        .name = "snapshot_cache_off",
        .flag = "--snapshot-cache-off",
        .help = "snapshot encode cache layers to switch off, comma-separated, to measure what "
                "each saves (the bytes sent stay the same): streams, deltas, world_baselines, "
                "walks, whole_world_start or all; empty: none",
        .kind = Kind::Text,
        .text = &text_of<&S::game, &GameConfig::snapshot_cache_off>,
        .allow_empty = true},
    // Handshakes and connect tokens (PROTOCOL.md Game channel transport §limits).
    Key{.section = "game",
        .name = "max_half_open_per_host",
        .flag = "--max-half-open-per-host",
        .help = "game handshakes in progress from one host (an IPv4 address or an IPv6 /64); "
                "more are dropped",
        .integer = &integer_of<&S::game, &GameConfig::max_half_open_per_host>,
        .min = 1,
        .max = 65'536},
    Key{.section = "game",
        .name = "max_clients_per_host",
        .flag = "--max-clients-per-host",
        .help = "connected game clients from one host (an IPv4 address or an IPv6 /64); more "
                "are denied",
        .integer = &integer_of<&S::game, &GameConfig::max_clients_per_host>,
        .min = 1,
        .max = 4096},
    Key{.section = "game",
        .name = "max_tracked_addresses",
        .flag = "--max-tracked-addresses",
        .help = "unconnected addresses with a packet budget (only senders of a well-formed "
                "connection request are tracked)",
        .integer = &integer_of<&S::game, &GameConfig::max_tracked_addresses>,
        .min = 1,
        .max = 1 << 20},
    Key{.section = "game",
        .name = "max_used_tokens",
        .flag = "--max-used-tokens",
        .help = "connect tokens remembered until they expire (a token opens one handshake); "
                "when full, new handshakes wait",
        .integer = &integer_of<&S::game, &GameConfig::max_used_tokens>,
        .min = 1,
        .max = 1 << 24},
    Key{.section = "game",
        .name = "token_reuse_ms",
        .flag = "--token-reuse-ms",
        .help = "a join within this long of the account's last unused connect token gets that "
                "token again instead of a new one; 0: a new token every time",
        .integer = &integer_of<&S::game, &GameConfig::token_reuse_ms>,
        .min = 0,
        .max = 10'000},
    Key{.section = "matches",
        .name = "count",
        .flag = "--matches",
        .help = "matches opened at start (more are created over the control channel)",
        .integer = &integer_of<&S::matches, &MatchesConfig::count>,
        .min = 0,
        .max = 256},
    Key{.section = "matches",
        .name = "max_players",
        .flag = "--match-max-players",
        .help = "players per match opened at start",
        .integer = &integer_of<&S::matches, &MatchesConfig::max_players>,
        .min = 1,
        .max = 64},
    Key{.section = "matches",
        .name = "maps",
        .flag = "--maps",
        .help = "map files in rotation order: the matches opened at start play the first, and a "
                "match that ends is followed by one on the next; each is loaded at start",
        .kind = Kind::TextList,
        .texts = &texts_of<&S::matches, &MatchesConfig::maps>},
    Key{.section = "matches",
        .name = "mode",
        .flag = "--mode",
        .help = "ffa: free-for-all; tdm: team deathmatch (red against blue)",
        .kind = Kind::Choice,
        .choices = "ffa|tdm",
        .get_choice = [](const ServerConfig& c) -> std::string_view { return c.matches.mode; },
        .set_choice =
            [](ServerConfig& c, std::string_view text) {
              if (text != "ffa" && text != "tdm") return false;
              c.matches.mode = std::string{text};
              return true;
            }},
    Key{.section = "matches",
        .name = "frag_limit",
        .flag = "--frag-limit",
        .help = "score that ends the match, of one player (ffa) or one team (tdm); 0: none",
        .integer = &integer_of<&S::matches, &MatchesConfig::frag_limit>,
        .min = 0,
        .max = 1'000},
    Key{.section = "matches",
        .name = "time_limit_s",
        .flag = "--time-limit-s",
        .help = "seconds after the warm-up that end the match; 0: none",
        .kind = Kind::Number,
        .number = &number_of<&S::matches, &MatchesConfig::time_limit_s>,
        .min_number = 0,
        .max_number = 86'400},
    Key{.section = "matches",
        .name = "warmup_s",
        .flag = "--warmup-s",
        .help = "seconds of warm-up once min_players are in, before the match counts",
        .kind = Kind::Number,
        .number = &number_of<&S::matches, &MatchesConfig::warmup_s>,
        .min_number = 0,
        .max_number = 600},
    Key{.section = "matches",
        .name = "min_players",
        .flag = "--min-players",
        .help = "players needed before the warm-up starts; at most max_players",
        .integer = &integer_of<&S::matches, &MatchesConfig::min_players>,
        .min = 1,
        .max = 64},
    Key{.section = "matches",
        .name = "respawn_delay_s",
        .flag = "--respawn-delay-s",
        .help = "seconds a dead player waits before it respawns",
        .kind = Kind::Number,
        .number = &number_of<&S::matches, &MatchesConfig::respawn_delay_s>,
        .min_number = 0,
        .max_number = 60},
    Key{.section = "matches",
        .name = "spawn_protection_s",
        .flag = "--spawn-protection-s",
        .help = "seconds a player takes no damage after it spawns",
        .kind = Kind::Number,
        .number = &number_of<&S::matches, &MatchesConfig::spawn_protection_s>,
        .min_number = 0,
        .max_number = 10},
    Key{.section = "matches",
        .name = "self_damage",
        .flag = "--self-damage",
        .help = "fraction of the damage of its own explosions a player takes (0: none)",
        .kind = Kind::Number,
        .number = &number_of<&S::matches, &MatchesConfig::self_damage>,
        .min_number = 0,
        .max_number = 1},
    Key{.section = "matches",
        .name = "friendly_fire",
        .flag = "--friendly-fire",
        .help = "tdm: team-mates damage each other",
        .kind = Kind::Bool,
        .boolean = &boolean_of<&S::matches, &MatchesConfig::friendly_fire>},
    Key{.section = "matches",
        .name = "seed",
        .flag = "--seed",
        .help = "seed of each match's random numbers (weapon spread); 0: a random seed for each "
                "match, logged",
        .integer = &integer_of<&S::matches, &MatchesConfig::seed>,
        .min = 0,
        .max = std::numeric_limits<int>::max()},
    Key{.section = "matches",
        .name = "lag_compensation",
        .flag = "--lag-compensation",
        .help = "rewind the targets of a shot to what the shooter saw",
        .kind = Kind::Bool,
        .boolean = &boolean_of<&S::matches, &MatchesConfig::lag_compensation>},
    Key{.section = "matches",
        .name = "max_rewind_ms",
        .flag = "--max-rewind-ms",
        .help = "milliseconds lag compensation rewinds at most (latency and interpolation)",
        .kind = Kind::Number,
        .number = &number_of<&S::matches, &MatchesConfig::max_rewind_ms>,
        .min_number = 0,
        .max_number = 250},
    Key{.section = "matches",
        .name = "record",
        .flag = "--record-matches",
        .help = "write a recording of every match to recordings_dir (replay it with "
                "ricochet-replay)",
        .kind = Kind::Bool,
        .boolean = &boolean_of<&S::matches, &MatchesConfig::record>},
    Key{.section = "matches",
        .name = "recordings_dir",
        .flag = "--recordings-dir",
        .help = "directory of the match recordings; a relative path is under server.data_dir",
        .kind = Kind::Text,
        .text = &text_of<&S::matches, &MatchesConfig::recordings_dir>},
    // Seats and created matches (issue 29: one address, one account cannot fill the server).
    Key{.section = "matches",
        .name = "seats_per_address",
        .flag = "--seats-per-address",
        .help = "seats one address holds, reserved or taken, all matches together (an IPv4 "
                "address, or an IPv6 /64)",
        .integer = &integer_of<&S::matches, &MatchesConfig::seats_per_address>,
        .min = 1,
        .max = 4096},
    Key{.section = "matches",
        .name = "reserved_seats_per_match",
        .flag = "--reserved-seats-per-match",
        .help = "seats of one match reserved by a join whose game channel has not connected yet "
                "(never more than half the match's seats)",
        .integer = &integer_of<&S::matches, &MatchesConfig::reserved_seats_per_match>,
        .min = 1,
        .max = 64},
    Key{.section = "matches",
        .name = "max_created",
        .flag = "--max-created-matches",
        .help = "matches created over the control channel, open at once",
        .integer = &integer_of<&S::matches, &MatchesConfig::max_created>,
        .min = 0,
        .max = 256},
    Key{.section = "matches",
        .name = "max_created_per_account",
        .flag = "--max-created-matches-per-account",
        .help = "of those, created by one account",
        .integer = &integer_of<&S::matches, &MatchesConfig::max_created_per_account>,
        .min = 0,
        .max = 256},
    Key{.section = "matches",
        .name = "creates_per_minute",
        .flag = "--match-creates-per-minute",
        .help = "matches created per minute, the whole server (in bursts of 10)",
        .kind = Kind::Number,
        .number = &number_of<&S::matches, &MatchesConfig::creates_per_minute>,
        .min_number = 0.1,
        .max_number = 10'000},
    Key{.section = "matches",
        .name = "creates_per_account_per_minute",
        .flag = "--match-creates-per-account-per-minute",
        .help = "matches created per minute by one account (one at a time)",
        .kind = Kind::Number,
        .number = &number_of<&S::matches, &MatchesConfig::creates_per_account_per_minute>,
        .min_number = 0.1,
        .max_number = 10'000},
    Key{.section = "matches",
        .name = "empty_close_after_s",
        .flag = "--empty-match-close-after-s",
        .help = "seconds a created match stays open with nobody seated (the matches opened at "
                "start stay)",
        .kind = Kind::Number,
        .number = &number_of<&S::matches, &MatchesConfig::empty_close_after_s>,
        .min_number = 1,
        .max_number = 86'400},
    Key{.section = "admin",
        .name = "bind",
        .flag = "--admin-bind",
        .help = "address of the admin HTTP port (/metrics, /healthz, /readyz); keep it private",
        .kind = Kind::Address,
        .text = &text_of<&S::admin, &AdminConfig::bind>},
    Key{.section = "admin",
        .name = "port",
        .flag = "--admin-port",
        .help = "TCP port of the admin HTTP server; 0: any free port",
        .integer = &integer_of<&S::admin, &AdminConfig::port>,
        .min = 0,
        .max = kMaxPort},
    // Exposing the admin port (issue 29).
    Key{.section = "admin",
        .name = "token_file",
        .flag = "--admin-token-file",
        .help = "file holding a bearer token /metrics requires (read at start, surrounding "
                "whitespace ignored); empty: none (keep the port private then)",
        .kind = Kind::Text,
        .text = &text_of<&S::admin, &AdminConfig::token_file>,
        .allow_empty = true},
    Key{.section = "admin",
        .name = "max_connections",
        .flag = "--admin-max-connections",
        .help = "admin HTTP connections open at once (a new one closes the one idle longest)",
        .integer = &integer_of<&S::admin, &AdminConfig::max_connections>,
        .min = 1,
        .max = 1024},
    Key{.section = "admin",
        .name = "max_connections_per_address",
        .flag = "--admin-max-connections-per-address",
        .help = "admin HTTP connections open at once from one address (IPv4, or IPv6 /64), "
                "its event streams not counted",
        .integer = &integer_of<&S::admin, &AdminConfig::max_connections_per_address>,
        .min = 1,
        .max = 1024},
    Key{.section = "admin",
        .name = "max_streams_per_address",
        .flag = "--admin-max-streams-per-address",
        .help = "event streams (a dashboard tab each) open at once from one address, beside its "
                "other connections; one more is answered 503",
        .integer = &integer_of<&S::admin, &AdminConfig::max_streams_per_address>,
        .min = 1,
        .max = 1024},
    Key{.section = "admin",
        .name = "signin_failures_per_minute",
        .flag = "--admin-signin-failures-per-minute",
        .help = "wrong tokens the dashboard's sign-in takes from one address (IPv4, or IPv6 /64) "
                "in a minute from its first; then 429 until that minute ends",
        .integer = &integer_of<&S::admin, &AdminConfig::signin_failures_per_minute>,
        .min = 1,
        .max = 1000},
    // The dashboard's live spectator feed (issue 32).
    Key{.section = "dashboard",
        .name = "live_feed_hz",
        .flag = "--dashboard-live-feed-hz",
        .help = "frames per second (of server time) a watched match publishes to its live view; "
                "none while nobody watches",
        .integer = &integer_of<&S::dashboard, &DashboardConfig::live_feed_hz>,
        .min = 1,
        .max = 60},
    Key{.section = "dashboard",
        .name = "live_feed_max_viewers",
        .flag = "--dashboard-live-feed-max-viewers",
        .help = "viewers watching one match's live view at once (one more is refused)",
        .integer = &integer_of<&S::dashboard, &DashboardConfig::live_feed_max_viewers>,
        .min = 1,
        .max = 64},
    // The dashboard's replays of recordings, on threads of their own.
    Key{.section = "dashboard",
        .name = "replay_workers",
        .flag = "--dashboard-replay-workers",
        .help = "threads replaying recordings for the dashboard (never a match's thread)",
        .integer = &integer_of<&S::dashboard, &DashboardConfig::replay_workers>,
        .min = 1,
        .max = kMaxReplayWorkers},
    Key{.section = "dashboard",
        .name = "max_replays",
        .flag = "--dashboard-max-replays",
        .help = "replays queued or running at once (at least replay_workers); one more is "
                "answered busy",
        .integer = &integer_of<&S::dashboard, &DashboardConfig::max_replays>,
        .min = 1,
        .max = kMaxReplaysAtOnce},
    Key{.section = "dashboard",
        .name = "replay_memory_mb",
        .flag = "--dashboard-replay-memory-mb",
        .help = "MiB of replay frames, running and cached together (least recently used "
                "dropped first)",
        .integer = &integer_of<&S::dashboard, &DashboardConfig::replay_memory_mb>,
        .min = kMinReplayMemoryMb,
        .max = kMaxReplayMemoryMb},
    // Agones (issue 31): the SDK sidecar is used when AGONES_SDK_HTTP_PORT is set.
    Key{.section = "agones",
        .name = "shutdown_after_matches",
        .flag = "--agones-shutdown-after-matches",
        .help = "under Agones: matches that end by themselves before the server asks Agones to "
                "shut its GameServer down (POST /shutdown); 0: never",
        .integer = &integer_of<&S::agones, &AgonesConfig::shutdown_after_matches>,
        .min = 0,
        .max = 1'000'000},
    // Placement across a fleet (issue 31).
    Key{.section = "placement",
        .name = "enabled",
        .flag = "--placement",
        .help = "keep a row in the fleet directory and answer find_match: auto (when db.url is "
                "PostgreSQL), on, off",
        .kind = Kind::Choice,
        .choices = "auto|on|off",
        .get_choice = [](const ServerConfig& c) -> std::string_view {
          return name(c.placement.enabled);
        },
        .set_choice =
            [](ServerConfig& c, std::string_view text) {
              return parse_enum(kPlacementModes, text, c.placement.enabled);
            }},
    Key{.section = "placement",
        .name = "advertise_host",
        .flag = "--advertise-host",
        .help = "the host (DNS name or IP address) players of other servers are sent to; empty: "
                "this machine's host name, or under Agones the GameServer's status.address",
        .kind = Kind::Text,
        .text = &text_of<&S::placement, &PlacementConfig::advertise_host>,
        .allow_empty = true},
    Key{.section = "placement",
        .name = "advertise_control_port",
        .flag = "--advertise-control-port",
        .help = "control port (TCP) players are sent to; 0: the bound one, or under Agones the "
                "GameServer's port named control",
        .integer = &integer_of<&S::placement, &PlacementConfig::advertise_control_port>,
        .min = 0,
        .max = kMaxPort},
    Key{.section = "placement",
        .name = "advertise_game_port",
        .flag = "--advertise-game-port",
        .help = "game port (UDP) players are sent to; 0: the bound one, or under Agones the "
                "GameServer's port named game",
        .integer = &integer_of<&S::placement, &PlacementConfig::advertise_game_port>,
        .min = 0,
        .max = kMaxPort},
    Key{.section = "placement",
        .name = "advertise_admin_port",
        .flag = "--advertise-admin-port",
        .help = "admin port (TCP: /metrics, /fleet) the directory lists for tools and dashboards; "
                "0: the bound one when admin.bind is beyond loopback or advertise_host is "
                "loopback, else none (under Agones: none)",
        .integer = &integer_of<&S::placement, &PlacementConfig::advertise_admin_port>,
        .min = 0,
        .max = kMaxPort},
    Key{.section = "placement",
        .name = "heartbeat_s",
        .flag = "--placement-heartbeat-s",
        .help = "seconds between two writes of this server's directory row",
        .integer = &integer_of<&S::placement, &PlacementConfig::heartbeat_s>,
        .min = 1,
        .max = 60},
    Key{.section = "placement",
        .name = "server_ttl_s",
        .flag = "--placement-server-ttl-s",
        .help = "seconds without a heartbeat after which a server is no longer placed on; at "
                "least twice heartbeat_s, well above the clock skew between servers",
        .integer = &integer_of<&S::placement, &PlacementConfig::server_ttl_s>,
        .min = 2,
        .max = 3600},
    Key{.section = "placement",
        .name = "ticket_lifetime_s",
        .flag = "--placement-ticket-lifetime-s",
        .help = "seconds a ticket holds its seat and may be used",
        .integer = &integer_of<&S::placement, &PlacementConfig::ticket_lifetime_s>,
        .min = 1,
        .max = 3600},
    Key{.section = "placement",
        .name = "find_match_per_minute",
        .flag = "--find-match-per-minute",
        .help = "find_match requests per minute from one account (in bursts of 5)",
        .kind = Kind::Number,
        .number = &number_of<&S::placement, &PlacementConfig::find_match_per_minute>,
        .min_number = 0.1,
        .max_number = 10'000},
    Key{.section = "log",
        .name = "level",
        .flag = "--log-level",
        .help = "least severe level written",
        .kind = Kind::Choice,
        .choices = "trace|debug|info|warn|error|critical|off",
        .get_choice = [](const ServerConfig& c) -> std::string_view { return name(c.log.level); },
        .set_choice =
            [](ServerConfig& c, std::string_view text) {
              return parse_enum(kLogLevels, text, c.log.level);
            }},
    Key{.section = "log",
        .name = "format",
        .flag = "--log-format",
        .help = "text lines, or JSON lines (one object per line)",
        .kind = Kind::Choice,
        .choices = "text|json",
        .get_choice = [](const ServerConfig& c) -> std::string_view { return name(c.log.format); },
        .set_choice =
            [](ServerConfig& c, std::string_view text) {
              return parse_enum(kLogFormats, text, c.log.format);
            }},
};

constexpr std::array<std::string_view, 11> kSections = {"server", "db",        "tls",   "control",
                                                        "game",   "matches",   "admin", "dashboard",
                                                        "agones", "placement", "log"};

}  // namespace

std::string Key::full_name() const {
  std::string full{section};
  full += '.';
  full += name;
  return full;
}

std::span<const Key> all() {
  return kKeys;
}

std::span<const std::string_view> sections() {
  return kSections;
}

const Key* find(std::string_view section, std::string_view name) {
  for (const Key& key : kKeys) {
    if (key.section == section && key.name == name) return &key;
  }
  return nullptr;
}

std::string value_text(const Key& key, const ServerConfig& config) {
  // The accessors take a mutable config; reading through them changes nothing.
  auto& mutable_config = const_cast<ServerConfig&>(config);
  switch (key.kind) {
    case Kind::Integer:
      return std::to_string(key.integer(mutable_config));
    case Kind::Text:
    case Kind::Address:
      return key.text(mutable_config);
    case Kind::Choice:
      return std::string{key.get_choice(config)};
    case Kind::Number:
      return number_text(key.number(mutable_config));
    case Kind::Bool:
      return key.boolean(mutable_config) ? "true" : "false";
    case Kind::TextList: {
      std::string joined;
      for (const std::string& text : key.texts(mutable_config)) {
        if (!joined.empty()) joined += ',';
        joined += text;
      }
      return joined;
    }
  }
  return {};
}

std::string value_toml(const Key& key, const ServerConfig& config) {
  auto& mutable_config = const_cast<ServerConfig&>(config);
  switch (key.kind) {
    case Kind::Integer:
    case Kind::Bool:
      return value_text(key, config);
    case Kind::Number: {
      // A float in TOML, so that the sample shows the kind: 10 is written 10.0.
      std::string text = number_text(key.number(mutable_config));
      if (text.find_first_of(".en") == std::string::npos) text += ".0";
      return text;
    }
    case Kind::Text:
    case Kind::Address:
    case Kind::Choice:
      return toml_quote(value_text(key, config));
    case Kind::TextList: {
      std::string array = "[";
      for (const std::string& text : key.texts(mutable_config)) {
        if (array.size() > 1) array += ", ";
        array += toml_quote(text);
      }
      return array + "]";
    }
  }
  return {};
}

std::string allowed_text(const Key& key) {
  switch (key.kind) {
    case Kind::Integer:
      return std::to_string(key.min) + ".." + std::to_string(key.max);
    case Kind::Number:
      return number_text(key.min_number) + ".." + number_text(key.max_number);
    case Kind::Bool:
      return "true or false";
    case Kind::Text:
      return key.allow_empty ? "any text" : "non-empty";
    case Kind::TextList:
      return "one or more non-empty";
    case Kind::Address:
      return "an IP address";
    case Kind::Choice:
      return "one of " + std::string{key.choices};
  }
  return {};
}

std::string check(const Key& key, const ServerConfig& config) {
  auto& mutable_config = const_cast<ServerConfig&>(config);
  switch (key.kind) {
    case Kind::Integer: {
      const int value = key.integer(mutable_config);
      if (value >= key.min && value <= key.max) return {};
      return key.full_name() + " must be " + allowed_text(key) + ", got " + std::to_string(value);
    }
    case Kind::Number: {
      const double value = key.number(mutable_config);
      if (value >= key.min_number && value <= key.max_number) return {};  // false for NaN
      return key.full_name() + " must be " + allowed_text(key) + ", got " + number_text(value);
    }
    case Kind::Text:
      if (key.allow_empty || !key.text(mutable_config).empty()) return {};
      return key.full_name() + " must be non-empty, got \"\"";
    case Kind::TextList: {
      const std::vector<std::string>& texts = key.texts(mutable_config);
      if (texts.empty()) return key.full_name() + " must list one or more, got none";
      for (std::size_t i = 0; i < texts.size(); ++i) {
        if (!texts[i].empty()) continue;
        std::string problem = key.full_name();
        problem += " must list non-empty names, got \"\" at ";
        problem += std::to_string(i + 1);
        return problem;
      }
      return {};
    }
    case Kind::Address: {
      const std::string& text = key.text(mutable_config);
      boost::system::error_code error;
      boost::asio::ip::make_address(text, error);
      if (!error) return {};
      return key.full_name() + " must be an IP address (e.g. 0.0.0.0, 127.0.0.1 or ::), got \"" +
             text + "\"";
    }
    case Kind::Choice:
    case Kind::Bool:
      return {};  // set_choice and assign_text accept only a valid value
  }
  return {};
}

std::string assign_text(const Key& key, std::string_view text, ServerConfig& config) {
  switch (key.kind) {
    case Kind::Integer: {
      long long value = 0;
      const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
      if (error == std::errc::result_out_of_range ||
          (error == std::errc{} && end == text.data() + text.size() &&
           (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max()))) {
        return key.full_name() + " must be " + allowed_text(key) + ", got " + std::string{text};
      }
      if (error != std::errc{} || end != text.data() + text.size()) {
        return key.full_name() + " must be an integer " + allowed_text(key) + ", got \"" +
               std::string{text} + "\"";
      }
      key.integer(config) = static_cast<int>(value);
      return {};
    }
    case Kind::Number: {
      double value = 0;
      const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
      if (error != std::errc{} || end != text.data() + text.size() || !std::isfinite(value)) {
        return key.full_name() + " must be a number " + allowed_text(key) + ", got \"" +
               std::string{text} + "\"";
      }
      key.number(config) = value;
      return {};
    }
    case Kind::Bool:
      if (text == "true" || text == "false") {
        key.boolean(config) = text == "true";
        return {};
      }
      return key.full_name() + " must be true or false, got \"" + std::string{text} + "\"";
    case Kind::TextList: {
      std::vector<std::string>& texts = key.texts(config);
      texts.clear();
      std::size_t start = 0;
      while (true) {
        const std::size_t comma = text.find(',', start);
        texts.emplace_back(text.substr(start, comma - start));
        if (comma == std::string_view::npos) break;
        start = comma + 1;
      }
      return {};
    }
    case Kind::Text:
    case Kind::Address:
      key.text(config) = std::string{text};
      return {};
    case Kind::Choice:
      if (key.set_choice(config, text)) return {};
      return key.full_name() + " must be one of " + std::string{key.choices} + ", got \"" +
             std::string{text} + "\"";
  }
  return {};
}

}  // namespace config_keys
}  // namespace ricochet::server
