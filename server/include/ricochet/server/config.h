#pragma once
/// The server's configuration: every key with its default, loaded from a TOML file and then
/// overridden by command-line flags (defaults < file < flags), validated once at start.
///
/// Every key lives in one table (config.cpp) that drives the TOML loader, the CLI11 flags and
/// their --help text, validate() and render_config_toml(); server/config/ricochet.toml is
/// render_config_toml(ServerConfig{}) and a test keeps the two equal.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ricochet/proto/snapshot_codec.h"
#include "ricochet/server/live_frame.h"

namespace ricochet::server {

enum class LogLevel { Trace, Debug, Info, Warn, Error, Critical, Off };
enum class LogFormat { Text, Json };

/// "trace", "debug", "info", "warn", "error", "critical", "off".
const char* name(LogLevel level);
/// "text", "json".
const char* name(LogFormat format);

/// [server]
struct ProcessConfig {
  std::string data_dir = "data";  ///< the database, the generated TLS pair; created if missing
  int threads = 0;                ///< match worker threads; 0: one per core
  int shutdown_grace_s = 10;      ///< SIGINT/SIGTERM: seconds to end matches and flush results
  /// Written once every socket listens: the bound ports, the certificate fingerprint and the
  /// process id as one JSON line, for scripts and tests (ports 0 let the kernel choose). Under
  /// data_dir unless absolute; empty: none.
  std::string ports_file;
};

/// Argon2id work per password hash: interactive (64 MiB, ~100 ms) protects the accounts;
/// minimum (a few µs) exists only for load tests whose thousands of bots sign in at once.
enum class PasswordHashing : std::uint8_t { Interactive, Minimum };
const char* name(PasswordHashing hashing);

/// [db]
struct DbConfig {
  std::string path = "ricochet.db";  ///< SQLite file; relative paths are under data_dir
  /// PostgreSQL (postgresql://user:password@host:port/dbname), shared by many servers; empty:
  /// the SQLite file at `path`.
  std::string url;
  /// Ended matches' results until the database has them (results_outbox.h); under data_dir
  /// unless absolute.
  std::string outbox_dir = "outbox";
  /// Seconds between two looks of a running server for the records other processes left in a
  /// shared outbox (ResultsOutbox::list_left), 1..3600.
  int outbox_rescan_s = 60;
  PasswordHashing password_hashing = PasswordHashing::Interactive;
  // --- abuse limits of accounts (issue 29) ---
  int registrations_per_hour_per_address = 10;  ///< an IPv4 address or IPv6 /64, in the database
  int password_thread_nice = 10;  ///< nice of the Argon2id threads (0..19): the ticks come first
};

/// [tls]
struct TlsConfig {
  std::string
      cert_file;  ///< PEM certificate chain; empty (with key_file): generate a pair in data_dir
  std::string key_file;  ///< PEM private key; set both or neither
};

/// [control] TLS control channel (TCP); maps onto ControlServerConfig and ControlLimits.
struct ControlConfig {
  std::string bind = "0.0.0.0";  ///< IP address literal
  int port = 7777;               ///< 0: any free port
  int max_connections = 4096;    ///< all addresses together
  int max_connections_per_address = 16;
  int handshake_timeout_ms = 5'000;  ///< accept to finished TLS handshake
  int frame_timeout_ms = 10'000;     ///< first byte of a frame to its last (slowloris)
  int idle_timeout_ms = 120'000;     ///< no whole frame for this long
  int login_timeout_ms = 30'000;     ///< handshake to login or resume; pings do not extend it
  int messages_per_second = 20;      ///< sustained requests per connection
  int message_burst = 40;            ///< requests a connection may send at once
  // Chat, across every session of an account and every player of a match (ChatLimiter).
  double chat_account_lines_per_s = 1;  ///< sustained chat lines per account
  int chat_account_burst = 5;           ///< chat lines an account may send at once
  double chat_match_lines_per_s = 8;    ///< sustained chat lines per match, all players
  int chat_match_burst = 20;            ///< chat lines a match may carry at once
};

/// [game] encrypted UDP game channel (GameServerConfig) and the fixed tick (MatchConfig).
struct GameConfig {
  std::string bind = "0.0.0.0";  ///< IP address literal
  int port = 7778;               ///< 0: any free port
  int tick_rate_hz = 60;
  int snapshot_rate_hz = 0;             ///< 0: the tick rate; otherwise at most the tick rate
  int max_catch_up_steps = 5;           ///< fixed steps one tick() may run after a stall
  int max_clients = 800;                ///< connected game clients, all matches together
  int max_half_open = 256;              ///< handshakes in progress (challenged, not yet connected)
  int address_packets_per_s = 20;       ///< datagrams per second from an unconnected address
  int client_packets_per_s = 250;       ///< datagrams per second from a connected client
  int bandwidth_kbps_per_client = 512;  ///< snapshot budget per client, kilobits per second
  /// Snapshot encode cache layers switched off, comma-separated (proto::SnapshotCacheLayers):
  /// a benchmark's switch, the bytes are the same; empty: every layer on.
  std::string snapshot_cache_off;
  // Handshakes and connect tokens (PROTOCOL.md Game channel transport §limits).
  int max_half_open_per_host = 16;   ///< handshakes in progress from one host (proto::host_key)
  int max_clients_per_host = 32;     ///< connected game clients from one host
  int max_tracked_addresses = 4096;  ///< unconnected addresses with a packet budget
  int max_used_tokens = 65536;       ///< connect tokens remembered until they expire
  int token_reuse_ms = 1000;         ///< a join this soon after the last unused token gets it again
};

/// [matches] the matches opened at start and the rules every match plays by; more matches come
/// through the control channel. Maps onto MatchRegistryConfig and MatchConfig (server.cpp).
struct MatchesConfig {
  int count = 4;         ///< matches opened at start
  int max_players = 16;  ///< per match opened at start
  /// Map files in rotation order: the first opens the matches at start, and each match that
  /// ends is followed by one on the next map. Every file is loaded and validated at start.
  std::vector<std::string> maps = {"server/maps/arena.toml", "server/maps/foundry.toml"};
  std::string mode = "ffa";         ///< "ffa" (free-for-all) or "tdm" (team deathmatch)
  int frag_limit = 20;              ///< a player's (ffa) or team's (tdm) score ending it; 0: none
  double time_limit_s = 600;        ///< after the warm-up, the match ends this late; 0: none
  double warmup_s = 10;             ///< once min_players are in, before the match counts
  int min_players = 2;              ///< players needed before the warm-up starts
  double respawn_delay_s = 2;       ///< dead this long before respawning
  double spawn_protection_s = 1.5;  ///< no damage taken this long after a spawn
  double self_damage = 0.5;         ///< fraction of its own explosions' damage a player takes
  bool friendly_fire = false;       ///< tdm: team-mates damage each other
  /// Seeds each match's random numbers (weapon spread); 0: a random seed for each match, logged.
  int seed = 0;
  bool lag_compensation = true;  ///< rewind the targets to what the shooter saw
  double max_rewind_ms = 250;    ///< lag compensation's total rewind cap
  bool record = true;            ///< write a recording of every match (ricochet-replay)
  std::string recordings_dir = "recordings";  ///< under data_dir unless absolute
  // Seats and created matches: MatchRegistryConfig::limits (SeatLimits).
  int seats_per_address = 8;                  ///< seats held from one address (IPv4, or IPv6 /64)
  int reserved_seats_per_match = 4;           ///< seats of one match reserved, not yet connected
  int max_created = 32;                       ///< created matches open at once
  int max_created_per_account = 1;            ///< created matches of one account open at once
  double creates_per_minute = 30;             ///< match creations per minute, the whole server
  double creates_per_account_per_minute = 2;  ///< match creations per minute, one account
  double empty_close_after_s = 60;  ///< a created match with nobody seated closes this late
};

/// [admin] HTTP: /metrics, /healthz, /readyz.
struct AdminConfig {
  std::string bind = "127.0.0.1";       ///< IP address literal; keep it private
  int port = 9100;                      ///< 0: any free port
  std::string token_file;               ///< bearer token /metrics requires; empty: none
  int max_connections = 32;             ///< open at once
  int max_connections_per_address = 8;  ///< its event streams not counted
  int max_streams_per_address = 4;      ///< event streams (dashboard tabs) from one address
  int signin_failures_per_minute = 10;  ///< wrong tokens at POST /signin per address, 1..1000
};

/// [dashboard]: the pages the admin port serves (issue 32): the live spectator feed of a match,
/// and replays of recordings on worker threads of their own (server/src/web/replay_jobs.h).
struct DashboardConfig {
  int live_feed_hz = 20;          ///< frames per second of a watched match, 1..60
  int live_feed_max_viewers = 8;  ///< viewers of one match at once, 1..64
  int replay_workers = 1;         ///< threads replaying recordings
  int max_replays = 4;            ///< replays queued or running at once; one more is refused busy
  int replay_memory_mb = 256;     ///< replay frames, running and cached together, MiB

  /// The match's side of the same numbers (live_frame.h).
  LiveFeedConfig live_feed() const { return LiveFeedConfig{live_feed_hz, live_feed_max_viewers}; }
};

/// [agones]: the Agones SDK, used when AGONES_SDK_HTTP_PORT is set (server/README.md).
struct AgonesConfig {
  int shutdown_after_matches = 0;  ///< matches ended by themselves before POST /shutdown; 0: never
};

/// Whether the server keeps a row in the fleet directory and answers find_match.
enum class PlacementMode : std::uint8_t { Auto, On, Off };
const char* name(PlacementMode mode);

/// [placement]: the fleet directory and FindMatch (PROTOCOL.md, Placement; OPERATIONS.md).
struct PlacementConfig {
  PlacementMode enabled = PlacementMode::Auto;  ///< auto: on when db.url is PostgreSQL
  /// What clients of other servers connect to: a DNS name or an IP address; empty: this
  /// machine's host name, or under Agones the GameServer's status.address (GET /gameserver).
  std::string advertise_host;
  int advertise_control_port = 0;  ///< 0: the bound control port (Agones: the port "control")
  int advertise_game_port = 0;     ///< 0: the bound game port (Agones: the port "game")
  /// The admin port (TCP) readers of the directory reach at advertise_host; 0: the bound one
  /// when it is reachable there, else none (admin_advertisement.h).
  int advertise_admin_port = 0;
  int heartbeat_s = 2;                ///< between two writes of the directory row
  int server_ttl_s = 10;              ///< a row this old is not placed on (and is purged)
  int ticket_lifetime_s = 30;         ///< a ticket holds its seat this long
  double find_match_per_minute = 30;  ///< per account, in bursts of 5

  /// enabled resolved against the database.
  bool on(const DbConfig& db) const;
};

/// [log]
struct LogConfig {
  LogLevel level = LogLevel::Info;
  LogFormat format = LogFormat::Text;  ///< text lines or JSON lines (one object per line)
};

struct ServerConfig {
  ProcessConfig server;
  DbConfig db;
  TlsConfig tls;
  ControlConfig control;
  GameConfig game;
  MatchesConfig matches;
  AdminConfig admin;
  DashboardConfig dashboard;
  AgonesConfig agones;
  PlacementConfig placement;
  LogConfig log;

  /// Every problem, one message each, naming the key, the allowed range and what came
  /// ("game.tick_rate_hz must be 10..128, got 0"); empty when the configuration is usable.
  std::vector<std::string> validate() const;

  /// threads, with 0 resolved to the number of cores (at least 1).
  int worker_threads() const;
  /// snapshot_rate_hz, with 0 resolved to the tick rate.
  int snapshot_rate_hz() const;
  /// db.path, under data_dir unless absolute.
  std::string db_file() const;
  /// What the store is opened on: db.url when set, else db_file().
  std::string db_url_or_path() const;
  /// db.outbox_dir, under data_dir unless absolute.
  std::string outbox_path() const;
  /// matches.recordings_dir, under data_dir unless absolute.
  std::string recordings_path() const;
  /// server.ports_file, under data_dir unless absolute; empty when none is asked for.
  std::string ports_file_path() const;
  /// Bytes of one snapshot payload from the bandwidth budget at the snapshot rate, at most
  /// kMaxSnapshotBytes (one datagram); validate() keeps it at least kMinSnapshotBytes.
  int snapshot_budget_bytes() const;
  /// game.snapshot_cache_off as the layers left on; nothing when it names an unknown layer.
  std::optional<proto::SnapshotCacheLayers> snapshot_cache_layers() const;

  static constexpr int kMinSnapshotBytes = 128;
  static constexpr int kMaxSnapshotBytes = 1100;
};

/// Applies the keys of a TOML document over `config`. Returns every problem: malformed TOML
/// (with line and column), an unknown key or table (named), a value of the wrong type or out of
/// range. `source_name` names the document in messages (the file's path).
std::vector<std::string> apply_config_toml(std::string_view toml_text, std::string_view source_name,
                                           ServerConfig& config);
/// Reads the file and applies it as apply_config_toml does; an unreadable file is one problem.
std::vector<std::string> apply_config_file(const std::string& path, ServerConfig& config);

/// The configuration as a TOML document with every key, its description and allowed range as
/// comments; render_config_toml(ServerConfig{}) is the sample server/config/ricochet.toml.
std::string render_config_toml(const ServerConfig& config);

/// What the command line asked for: run with a configuration, or exit at once.
struct ParseOutcome {
  std::optional<ServerConfig> config;  ///< set: run with it (file and flags applied, validated)
  int exit_code =
      0;  ///< when config is empty: 0 for --help, --version, --print-config; 2 for errors
  std::string text;  ///< when config is empty: print it (stdout when exit_code is 0, else stderr)
};

/// Parses `ricochet-server [--config PATH] [--KEY VALUE]...`: defaults, then the file named by
/// --config, then every flag given, then validate(). --help lists every flag with its default,
/// --version prints the version, --print-config prints the effective configuration as TOML.
ParseOutcome parse_command_line(int argc, const char* const* argv);

}  // namespace ricochet::server
