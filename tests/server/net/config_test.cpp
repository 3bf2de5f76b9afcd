#include "ricochet/server/config.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace ricochet::server::config_test {
namespace {

/// The repository's root (tests/server/CMakeLists.txt defines it).
std::filesystem::path source_root() {
  return RICOCHET_SOURCE_DIR;
}

/// Runs parse_command_line on "ricochet-server" followed by `args`.
ParseOutcome parse(std::vector<std::string> args) {
  args.insert(args.begin(), "ricochet-server");
  std::vector<const char*> argv;
  for (const std::string& arg : args) argv.push_back(arg.c_str());
  return parse_command_line(static_cast<int>(argv.size()), argv.data());
}

/// A TOML file in the temporary directory, removed at the end of the test.
class TempFile {
 public:
  explicit TempFile(const std::string& text)
      : path_(std::filesystem::temp_directory_path() /
              ("ricochet_config_test_" + std::to_string(::getpid()) + "_" +
               std::to_string(counter_++) + ".toml")) {
    std::ofstream{path_} << text;
  }
  ~TempFile() { std::filesystem::remove(path_); }
  std::string path() const { return path_.string(); }

 private:
  static inline int counter_ = 0;
  std::filesystem::path path_;
};

std::vector<std::string> problems_of(const std::string& toml) {
  ServerConfig config;
  return apply_config_toml(toml, "test.toml", config);
}

TEST(ServerConfig, DefaultsAreTheDocumentedOnes) {
  const ServerConfig config;
  EXPECT_TRUE(config.validate().empty());
  EXPECT_EQ(config.server.data_dir, "data");
  EXPECT_EQ(config.server.shutdown_grace_s, 10);
  EXPECT_EQ(config.control.bind, "0.0.0.0");
  EXPECT_EQ(config.control.port, 7777);
  EXPECT_EQ(config.game.port, 7778);
  EXPECT_EQ(config.admin.bind, "127.0.0.1");
  EXPECT_EQ(config.admin.port, 9100);
  EXPECT_EQ(config.game.tick_rate_hz, 60);
  EXPECT_EQ(config.snapshot_rate_hz(), 60);
  EXPECT_EQ(config.matches.count, 4);
  EXPECT_EQ(config.matches.max_players, 16);
  EXPECT_EQ(config.log.level, LogLevel::Info);
  EXPECT_EQ(config.log.format, LogFormat::Text);
  EXPECT_EQ(config.db.password_hashing, PasswordHashing::Interactive);
  EXPECT_GE(config.worker_threads(), 1);
  EXPECT_EQ(config.db_file(), "data/ricochet.db");
  EXPECT_EQ(config.snapshot_budget_bytes(), 1066);  // 512 kbps at 60 Hz
}

TEST(ServerConfig, SnapshotBudgetFollowsBandwidthAndRate) {
  ServerConfig config;
  config.game.snapshot_rate_hz = 20;
  EXPECT_EQ(config.snapshot_budget_bytes(), ServerConfig::kMaxSnapshotBytes);  // one datagram
  config.game.bandwidth_kbps_per_client = 64;
  EXPECT_EQ(config.snapshot_budget_bytes(), 400);
  EXPECT_TRUE(config.validate().empty());
}

TEST(ServerConfig, SnapshotCacheLayersAreSwitchedOffByNameAndAnUnknownNameIsAProblem) {
  ServerConfig config;
  ASSERT_TRUE(config.snapshot_cache_layers().has_value());  // empty: every layer on
  EXPECT_TRUE(config.snapshot_cache_layers()->streams);
  EXPECT_TRUE(config.snapshot_cache_layers()->whole_world_start);
  config.game.snapshot_cache_off = "streams,walks";
  ASSERT_TRUE(config.snapshot_cache_layers().has_value());
  const proto::SnapshotCacheLayers layers = *config.snapshot_cache_layers();
  EXPECT_FALSE(layers.streams);
  EXPECT_TRUE(layers.deltas);
  EXPECT_TRUE(layers.world_baselines);
  EXPECT_FALSE(layers.walks);
  EXPECT_TRUE(layers.whole_world_start);
  EXPECT_TRUE(config.validate().empty());
  config.game.snapshot_cache_off = "all";
  EXPECT_FALSE(config.snapshot_cache_layers()->deltas);
  EXPECT_FALSE(config.snapshot_cache_layers()->world_baselines);

  for (const char* wrong : {"stream", "streams,", "streams,,deltas", " deltas"}) {
    config.game.snapshot_cache_off = wrong;
    EXPECT_FALSE(config.snapshot_cache_layers().has_value()) << wrong;
    const std::vector<std::string> problems = config.validate();
    ASSERT_EQ(problems.size(), 1u) << wrong;
    EXPECT_NE(problems[0].find("game.snapshot_cache_off must list streams"), std::string::npos);
    EXPECT_NE(problems[0].find(std::string("got \"") + wrong + "\""), std::string::npos);
  }
  const ParseOutcome outcome = parse({"--snapshot-cache-off", "deltas"});
  ASSERT_TRUE(outcome.config.has_value()) << outcome.text;
  EXPECT_FALSE(outcome.config->snapshot_cache_layers()->deltas);
}

TEST(ServerConfig, NoArgumentsRunWithTheDefaults) {
  const ParseOutcome outcome = parse({});
  ASSERT_TRUE(outcome.config.has_value()) << outcome.text;
  EXPECT_EQ(outcome.config->game.tick_rate_hz, 60);
  EXPECT_EQ(render_config_toml(*outcome.config), render_config_toml(ServerConfig{}));
}

TEST(ServerConfig, FileOverridesDefaultsAndFlagsOverrideTheFile) {
  const TempFile file{
      "[game]\ntick_rate_hz = 30\nport = 8000\n[log]\nformat = \"json\"\n[db]\npath = "
      "\"/var/x.db\"\n"};
  const ParseOutcome outcome =
      parse({"--config", file.path(), "--tick-rate-hz", "20", "--log-level", "debug"});
  ASSERT_TRUE(outcome.config.has_value()) << outcome.text;
  const ServerConfig& config = *outcome.config;
  EXPECT_EQ(config.game.tick_rate_hz, 20);  // flag over file
  EXPECT_EQ(config.game.port, 8000);        // file over default
  EXPECT_EQ(config.log.format, LogFormat::Json);
  EXPECT_EQ(config.log.level, LogLevel::Debug);
  EXPECT_EQ(config.control.port, 7777);  // default
  EXPECT_EQ(config.db_file(), "/var/x.db");
}

TEST(ServerConfig, FlagsApplyWithoutAFile) {
  const ParseOutcome outcome =
      parse({"--admin-port", "0",      "--control-port", "0",     "--game-port", "0",
             "--data-dir",   "/tmp/r", "--matches",      "0",     "--maps",      "m.toml,n.toml",
             "--admin-bind", "::1",    "--tls-cert",     "c.pem", "--tls-key",   "k.pem",
             "--threads",    "3"});
  ASSERT_TRUE(outcome.config.has_value()) << outcome.text;
  EXPECT_EQ(outcome.config->admin.port, 0);
  EXPECT_EQ(outcome.config->admin.bind, "::1");
  EXPECT_EQ(outcome.config->matches.count, 0);
  EXPECT_EQ(outcome.config->matches.maps, (std::vector<std::string>{"m.toml", "n.toml"}));
  EXPECT_EQ(outcome.config->tls.cert_file, "c.pem");
  EXPECT_EQ(outcome.config->worker_threads(), 3);
  EXPECT_EQ(outcome.config->db_file(), "/tmp/r/ricochet.db");
}

TEST(ServerConfig, EveryRangeMessageNamesTheKeyTheRangeAndTheValue) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--tick-rate-hz", "0"}, "game.tick_rate_hz must be 10..128, got 0"},
      {{"--tick-rate-hz", "129"}, "game.tick_rate_hz must be 10..128, got 129"},
      {{"--threads", "-1"}, "server.threads must be 0..256, got -1"},
      {{"--shutdown-grace-s", "0"}, "server.shutdown_grace_s must be 1..300, got 0"},
      {{"--control-port", "65536"}, "control.port must be 0..65535, got 65536"},
      {{"--game-port", "-5"}, "game.port must be 0..65535, got -5"},
      {{"--admin-port", "70000"}, "admin.port must be 0..65535, got 70000"},
      {{"--max-connections", "0"}, "control.max_connections must be 1..1000000, got 0"},
      {{"--max-connections-per-address", "0"},
       "control.max_connections_per_address must be 1..1000000, got 0"},
      {{"--handshake-timeout-ms", "99"}, "control.handshake_timeout_ms must be 100..60000, got 99"},
      {{"--frame-timeout-ms", "600001"},
       "control.frame_timeout_ms must be 100..600000, got 600001"},
      {{"--idle-timeout-ms", "999"}, "control.idle_timeout_ms must be 1000..3600000, got 999"},
      {{"--snapshot-rate-hz", "-1"}, "game.snapshot_rate_hz must be 0..128, got -1"},
      {{"--max-catch-up-steps", "0"}, "game.max_catch_up_steps must be 1..64, got 0"},
      {{"--max-clients", "0"}, "game.max_clients must be 1..4096, got 0"},
      {{"--max-half-open", "65537"}, "game.max_half_open must be 1..65536, got 65537"},
      {{"--max-clients-per-host", "0"}, "game.max_clients_per_host must be 1..4096, got 0"},
      {{"--token-reuse-ms", "10001"}, "game.token_reuse_ms must be 0..10000, got 10001"},
      {{"--address-packets-per-s", "0"}, "game.address_packets_per_s must be 1..1000000, got 0"},
      {{"--client-packets-per-s", "0"}, "game.client_packets_per_s must be 1..1000000, got 0"},
      {{"--bandwidth-kbps", "15"}, "game.bandwidth_kbps_per_client must be 16..100000, got 15"},
      {{"--bandwidth-kbps", "61"},
       "game.bandwidth_kbps_per_client must be at least 62 at 60 snapshots/s (128 bytes per "
       "snapshot), got 61"},
      {{"--matches", "257"}, "matches.count must be 0..256, got 257"},
      {{"--match-max-players", "65"}, "matches.max_players must be 1..64, got 65"},
      {{"--data-dir", ""}, "server.data_dir must be non-empty, got \"\""},
      {{"--db-path", ""}, "db.path must be non-empty, got \"\""},
      {{"--maps", ""}, "matches.maps must list non-empty names, got \"\" at 1"},
      {{"--maps", "a.toml,,b.toml"}, "matches.maps must list non-empty names, got \"\" at 2"},
      {{"--mode", "ctf"}, "--mode: matches.mode must be one of ffa|tdm, got \"ctf\""},
      {{"--frag-limit", "1001"}, "matches.frag_limit must be 0..1000, got 1001"},
      {{"--time-limit-s", "-0.5"}, "matches.time_limit_s must be 0..86400, got -0.5"},
      {{"--time-limit-s", "long"},
       "--time-limit-s: matches.time_limit_s must be a number 0..86400, got \"long\""},
      {{"--time-limit-s", "inf"},
       "--time-limit-s: matches.time_limit_s must be a number 0..86400, got \"inf\""},
      {{"--warmup-s", "-1"}, "matches.warmup_s must be 0..600, got -1"},
      {{"--min-players", "0"}, "matches.min_players must be 1..64, got 0"},
      {{"--min-players", "17"}, "matches.min_players must be 1..matches.max_players (16), got 17"},
      {{"--respawn-delay-s", "61"}, "matches.respawn_delay_s must be 0..60, got 61"},
      {{"--spawn-protection-s", "10.5"}, "matches.spawn_protection_s must be 0..10, got 10.5"},
      {{"--self-damage", "1.5"}, "matches.self_damage must be 0..1, got 1.5"},
      {{"--friendly-fire", "yes"},
       "--friendly-fire: matches.friendly_fire must be true or false, got \"yes\""},
      {{"--seed", "-1"}, "matches.seed must be 0..2147483647, got -1"},
      {{"--max-rewind-ms", "250.5"}, "matches.max_rewind_ms must be 0..250, got 250.5"},
      {{"--recordings-dir", ""}, "matches.recordings_dir must be non-empty, got \"\""},
      {{"--seats-per-address", "0"}, "matches.seats_per_address must be 1..4096, got 0"},
      {{"--reserved-seats-per-match", "65"},
       "matches.reserved_seats_per_match must be 1..64, got 65"},
      {{"--max-created-matches-per-account", "33"},
       "matches.max_created_per_account must be 0..matches.max_created (32), got 33"},
      {{"--match-creates-per-minute", "0"}, "matches.creates_per_minute must be 0.1..10000, got 0"},
      {{"--empty-match-close-after-s", "0.5"},
       "matches.empty_close_after_s must be 1..86400, got 0.5"},
      {{"--admin-max-connections", "0"}, "admin.max_connections must be 1..1024, got 0"},
      {{"--dashboard-live-feed-hz", "0"}, "dashboard.live_feed_hz must be 1..60, got 0"},
      {{"--dashboard-live-feed-hz", "61"}, "dashboard.live_feed_hz must be 1..60, got 61"},
      {{"--dashboard-live-feed-max-viewers", "65"},
       "dashboard.live_feed_max_viewers must be 1..64, got 65"},
      {{"--admin-max-connections-per-address", "33"},
       "admin.max_connections_per_address must be 1..admin.max_connections (32), got 33"},
      {{"--admin-max-streams-per-address", "33"},
       "admin.max_streams_per_address must be 1..admin.max_connections (32), got 33"},
      {{"--admin-signin-failures-per-minute", "0"},
       "admin.signin_failures_per_minute must be 1..1000, got 0"},
      {{"--control-bind", "localhost"},
       "control.bind must be an IP address (e.g. 0.0.0.0, 127.0.0.1 or ::), got \"localhost\""},
      {{"--game-bind", "1.2.3"},
       "game.bind must be an IP address (e.g. 0.0.0.0, 127.0.0.1 or ::), got \"1.2.3\""},
      {{"--admin-bind", ""},
       "admin.bind must be an IP address (e.g. 0.0.0.0, 127.0.0.1 or ::), got \"\""},
      {{"--log-level", "loud"},
       "--log-level: log.level must be one of trace|debug|info|warn|error|critical|off, got "
       "\"loud\""},
      {{"--log-format", "xml"}, "--log-format: log.format must be one of text|json, got \"xml\""},
      {{"--password-hashing", "none"},
       "--password-hashing: db.password_hashing must be one of interactive|minimum, got \"none\""},
      {{"--tick-rate-hz", "fast"},
       "--tick-rate-hz: game.tick_rate_hz must be an integer 10..128, got \"fast\""},
      {{"--tick-rate-hz", "99999999999"},
       "--tick-rate-hz: game.tick_rate_hz must be 10..128, got 99999999999"},
      {{"--tick-rate-hz", "30", "--snapshot-rate-hz", "31"},
       "game.snapshot_rate_hz must be 0..game.tick_rate_hz (30; 0: the tick rate), got 31"},
      {{"--tls-cert", "c.pem"},
       "tls.cert_file and tls.key_file must be both set or both empty, got cert_file \"c.pem\" "
       "and key_file \"\""},
      {{"--admin-port", "7777"},
       "admin.port must differ from control.port (both are TCP), got "
       "7777 for both"},
      {{"--max-connections", "4"},
       "control.max_connections_per_address must be 1..control.max_connections (4), got 16"},
  };
  for (const auto& [args, message] : cases) {
    const ParseOutcome outcome = parse(args);
    EXPECT_FALSE(outcome.config.has_value()) << message;
    EXPECT_EQ(outcome.exit_code, 2) << message;
    EXPECT_NE(outcome.text.find(message + "\n"), std::string::npos)
        << "expected: " << message << "\ngot: " << outcome.text;
  }
}

TEST(ServerConfig, ValidateReportsEveryProblemAtOnce) {
  ServerConfig config;
  config.game.tick_rate_hz = 0;
  config.admin.port = -1;
  config.server.data_dir.clear();
  EXPECT_EQ(config.validate(), (std::vector<std::string>{
                                   "server.data_dir must be non-empty, got \"\"",
                                   "game.tick_rate_hz must be 10..128, got 0",
                                   "admin.port must be 0..65535, got -1",
                               }));
}

TEST(ServerConfig, UnknownKeysAndTablesAreNamed) {
  EXPECT_EQ(problems_of("[game]\ntickrate = 30\n"),
            std::vector<std::string>{
                "test.toml:2:12: unknown key 'game.tickrate' (known keys in [game]: bind, port, "
                "tick_rate_hz, snapshot_rate_hz, max_catch_up_steps, max_clients, "
                "max_half_open, address_packets_per_s, client_packets_per_s, "
                "bandwidth_kbps_per_client, snapshot_cache_off, max_half_open_per_host, "
                "max_clients_per_host, max_tracked_addresses, max_used_tokens, "
                "token_reuse_ms)"});
  EXPECT_EQ(problems_of("[physics]\ngravity = 9\n"),
            std::vector<std::string>{
                "test.toml:1:1: unknown key 'physics' (known tables: server, db, tls, control, "
                "game, matches, admin, dashboard, agones, placement, log)"});
  EXPECT_EQ(problems_of("verbose = true\n"),
            std::vector<std::string>{
                "test.toml:1:11: unknown key 'verbose' (known tables: server, db, tls, control, "
                "game, matches, admin, dashboard, agones, placement, log)"});
  EXPECT_EQ(problems_of("game = 5\n"),
            std::vector<std::string>{"test.toml:1:8: 'game' must be a table ([game]), got an "
                                     "integer"});
}

TEST(ServerConfig, WrongTypesInTheFileAreNamed) {
  EXPECT_EQ(problems_of("[game]\ntick_rate_hz = \"fast\"\n"),
            std::vector<std::string>{
                "test.toml:2:16: game.tick_rate_hz must be an integer 10..128, got a string"});
  EXPECT_EQ(problems_of("[game]\ntick_rate_hz = 60.5\n"),
            std::vector<std::string>{
                "test.toml:2:16: game.tick_rate_hz must be an integer 10..128, got a float"});
  EXPECT_EQ(problems_of("[game]\nport = 10000000000\n"),
            std::vector<std::string>{"test.toml:2:8: game.port must be 0..65535, got 10000000000"});
  EXPECT_EQ(problems_of("[log]\nlevel = 3\n"),
            std::vector<std::string>{"test.toml:2:9: log.level must be a string, one of "
                                     "trace|debug|info|warn|error|critical|off, got an integer"});
  EXPECT_EQ(problems_of("[log]\nformat = \"yaml\"\n"),
            std::vector<std::string>{
                "test.toml:2:10: log.format must be one of text|json, got \"yaml\""});
  EXPECT_EQ(problems_of("[server]\ndata_dir = [\"a\"]\n"),
            std::vector<std::string>{
                "test.toml:2:12: server.data_dir must be a string, non-empty, got an array"});
}

TEST(ServerConfig, MatchRulesLoadFromTheFile) {
  ServerConfig config;
  EXPECT_TRUE(apply_config_toml("[matches]\n"
                                "maps = [\"a.toml\", \"b.toml\"]\n"
                                "mode = \"tdm\"\n"
                                "frag_limit = 50\n"
                                "time_limit_s = 300\n"  // an integer is a number too
                                "warmup_s = 2.5\n"
                                "min_players = 4\n"
                                "respawn_delay_s = 0.5\n"
                                "spawn_protection_s = 0\n"
                                "self_damage = 0.25\n"
                                "friendly_fire = true\n"
                                "seed = 1234\n"
                                "lag_compensation = false\n"
                                "max_rewind_ms = 100\n"
                                "record = false\n"
                                "recordings_dir = \"/srv/rec\"\n",
                                "test.toml", config)
                  .empty());
  EXPECT_TRUE(config.validate().empty());
  const MatchesConfig& m = config.matches;
  EXPECT_EQ(m.maps, (std::vector<std::string>{"a.toml", "b.toml"}));
  EXPECT_EQ(m.mode, "tdm");
  EXPECT_EQ(m.frag_limit, 50);
  EXPECT_EQ(m.time_limit_s, 300);
  EXPECT_EQ(m.warmup_s, 2.5);
  EXPECT_EQ(m.min_players, 4);
  EXPECT_EQ(m.respawn_delay_s, 0.5);
  EXPECT_EQ(m.spawn_protection_s, 0);
  EXPECT_EQ(m.self_damage, 0.25);
  EXPECT_TRUE(m.friendly_fire);
  EXPECT_EQ(m.seed, 1234);
  EXPECT_FALSE(m.lag_compensation);
  EXPECT_EQ(m.max_rewind_ms, 100);
  EXPECT_FALSE(m.record);
  EXPECT_EQ(config.recordings_path(), "/srv/rec");
  EXPECT_EQ(ServerConfig{}.recordings_path(), "data/recordings");
}

TEST(ServerConfig, ThePortsFileIsNoneUnlessAskedAndUnderTheDataDirWhenRelative) {
  EXPECT_EQ(ServerConfig{}.ports_file_path(), "");
  ParseOutcome relative = parse({"--data-dir", "/tmp/r", "--ports-file", "ports.json"});
  ASSERT_TRUE(relative.config) << relative.text;
  EXPECT_EQ(relative.config->ports_file_path(), "/tmp/r/ports.json");
  ParseOutcome absolute = parse({"--ports-file", "/run/ricochet/ports.json"});
  ASSERT_TRUE(absolute.config) << absolute.text;
  EXPECT_EQ(absolute.config->ports_file_path(), "/run/ricochet/ports.json");
}

TEST(ServerConfig, TheStoreIsSqliteUnlessAPostgresUrlIsGiven) {
  EXPECT_EQ(ServerConfig{}.db_url_or_path(), "data/ricochet.db");
  const std::string url = "postgresql://ricochet@db.internal:5432/ricochet";
  ParseOutcome flag = parse({"--db-url", url});
  ASSERT_TRUE(flag.config) << flag.text;
  EXPECT_EQ(flag.config->db_url_or_path(), url);
  ServerConfig from_file;
  EXPECT_TRUE(apply_config_toml("[db]\nurl = \"" + url + "\"\n", "test.toml", from_file).empty());
  EXPECT_EQ(from_file.db_url_or_path(), url);
  // Anything else is refused, without echoing what may be a password.
  ParseOutcome wrong = parse({"--db-url", "mysql://root:hunter2@db/ricochet"});
  EXPECT_FALSE(wrong.config);
  EXPECT_NE(wrong.text.find("db.url must start with postgresql://"), std::string::npos)
      << wrong.text;
  EXPECT_EQ(wrong.text.find("hunter2"), std::string::npos) << wrong.text;
}

TEST(ServerConfig, WrongTypesOfTheMatchRulesAreNamed) {
  EXPECT_EQ(problems_of("[matches]\nmaps = \"a.toml\"\n"),
            std::vector<std::string>{"test.toml:2:8: matches.maps must be an array of strings, "
                                     "one or more non-empty, got a string"});
  EXPECT_EQ(problems_of("[matches]\nmaps = [\"a.toml\", 3]\n"),
            std::vector<std::string>{
                "test.toml:2:8: matches.maps must be an array of strings, got an integer in it"});
  EXPECT_EQ(problems_of("[matches]\nself_damage = \"half\"\n"),
            std::vector<std::string>{
                "test.toml:2:15: matches.self_damage must be a number 0..1, got a string"});
  EXPECT_EQ(problems_of("[matches]\nfriendly_fire = 1\n"),
            std::vector<std::string>{
                "test.toml:2:17: matches.friendly_fire must be true or false, got an integer"});
  EXPECT_EQ(
      problems_of("[matches]\nmode = \"ctf\"\n"),
      std::vector<std::string>{"test.toml:2:8: matches.mode must be one of ffa|tdm, got \"ctf\""});
}

TEST(ServerConfig, MalformedTomlSaysWhere) {
  const std::vector<std::string> problems = problems_of("[game]\ntick_rate_hz = = 3\n");
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].rfind("test.toml:2:", 0), 0u) << problems[0];
  EXPECT_NE(problems[0].find("malformed TOML: "), std::string::npos) << problems[0];

  const TempFile file{"[game\n"};
  const ParseOutcome outcome = parse({"--config", file.path()});
  EXPECT_FALSE(outcome.config.has_value());
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_NE(outcome.text.find(file.path() + ":1:"), std::string::npos) << outcome.text;
}

TEST(ServerConfig, MissingFileIsOneProblem) {
  const ParseOutcome outcome = parse({"--config", "/nonexistent/ricochet.toml"});
  EXPECT_FALSE(outcome.config.has_value());
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_NE(outcome.text.find("cannot read config file \"/nonexistent/ricochet.toml\": No such "
                              "file or directory\n"),
            std::string::npos)
      << outcome.text;
  const ParseOutcome directory = parse({"--config", "/"});
  EXPECT_FALSE(directory.config.has_value());
  EXPECT_NE(directory.text.find("cannot read config file \"/\": it is a directory\n"),
            std::string::npos)
      << directory.text;
}

TEST(ServerConfig, HelpListsEveryFlagWithItsDefault) {
  const ParseOutcome outcome = parse({"--help"});
  EXPECT_FALSE(outcome.config.has_value());
  EXPECT_EQ(outcome.exit_code, 0);
  for (const char* expected : {"--config PATH",
                               "--version",
                               "--print-config",
                               "--tick-rate-hz INT=60",
                               "--control-port INT=7777",
                               "--game-port INT=7778",
                               "--admin-bind ADDRESS=127.0.0.1",
                               "--admin-port INT=9100",
                               "--log-level CHOICE=info",
                               "--log-format CHOICE=text",
                               "--password-hashing CHOICE=interactive",
                               "--shutdown-grace-s INT=10",
                               "--tls-cert TEXT=\"\"",
                               "--matches INT=4",
                               "--data-dir TEXT=data",
                               "--bandwidth-kbps INT=512",
                               "TOML game.tick_rate_hz",
                               "--maps LIST=server/maps/arena.toml,server/maps/foundry.toml",
                               "--mode CHOICE=ffa",
                               "--self-damage NUMBER=0.5",
                               "--friendly-fire BOOL=false",
                               "--time-limit-s NUMBER=600",
                               "--seed INT=0"}) {
    EXPECT_NE(outcome.text.find(expected), std::string::npos) << expected << "\n" << outcome.text;
  }
}

TEST(ServerConfig, VersionPrintsTheVersion) {
  const ParseOutcome outcome = parse({"--version"});
  EXPECT_FALSE(outcome.config.has_value());
  EXPECT_EQ(outcome.exit_code, 0);
  EXPECT_EQ(outcome.text, std::string{"ricochet-server "} + RICOCHET_VERSION + "\n");
}

TEST(ServerConfig, UnknownFlagIsAUsageError) {
  const ParseOutcome outcome = parse({"--tickrate", "3"});
  EXPECT_FALSE(outcome.config.has_value());
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_NE(outcome.text.find("--tickrate"), std::string::npos) << outcome.text;
}

TEST(ServerConfig, PrintConfigShowsTheEffectiveValues) {
  const ParseOutcome outcome = parse({"--print-config", "--tick-rate-hz", "30"});
  EXPECT_FALSE(outcome.config.has_value());
  EXPECT_EQ(outcome.exit_code, 0);
  EXPECT_NE(outcome.text.find("\ntick_rate_hz = 30\n"), std::string::npos) << outcome.text;
}

TEST(ServerConfig, RenderedConfigLoadsBackToTheSameValues) {
  ServerConfig changed;
  changed.game.tick_rate_hz = 33;
  changed.server.data_dir = "a \"quoted\" \\ dir";
  changed.log.format = LogFormat::Json;
  changed.matches.maps = {"a \"b\".toml", "c.toml"};
  changed.matches.self_damage = 0.1;
  changed.matches.time_limit_s = 1e-5;  // written with an exponent, read back exactly
  changed.matches.friendly_fire = true;
  ServerConfig loaded;
  EXPECT_TRUE(apply_config_toml(render_config_toml(changed), "rendered", loaded).empty());
  EXPECT_EQ(render_config_toml(loaded), render_config_toml(changed));
  EXPECT_EQ(loaded.server.data_dir, changed.server.data_dir);
  EXPECT_EQ(loaded.matches.maps, changed.matches.maps);
  EXPECT_EQ(loaded.matches.self_damage, 0.1);
  EXPECT_EQ(loaded.matches.time_limit_s, 1e-5);
  EXPECT_TRUE(loaded.matches.friendly_fire);
}

TEST(ServerConfig, PlacementIsOnWithPostgresOrWhenAskedAndItsTtlCoversTwoHeartbeats) {
  ServerConfig config;
  EXPECT_FALSE(config.placement.on(config.db));  // SQLite, auto
  config.db.url = "postgresql://ricochet@db/ricochet";
  EXPECT_TRUE(config.placement.on(config.db));
  config.placement.enabled = PlacementMode::Off;
  EXPECT_FALSE(config.placement.on(config.db));
  config.db.url.clear();
  config.placement.enabled = PlacementMode::On;
  EXPECT_TRUE(config.placement.on(config.db));
  EXPECT_TRUE(config.validate().empty());
  config.placement.heartbeat_s = 6;
  EXPECT_EQ(config.validate(),
            std::vector<std::string>{"placement.server_ttl_s must be at least twice "
                                     "placement.heartbeat_s (12), got 10"});
}

TEST(ServerConfig, SampleFileDocumentsEveryKeyWithItsDefault) {
  const std::filesystem::path sample = source_root() / "server/config/ricochet.toml";
  std::ifstream file{sample};
  ASSERT_TRUE(file) << sample;
  std::ostringstream text;
  text << file.rdbuf();
  EXPECT_EQ(text.str(), render_config_toml(ServerConfig{}))
      << "regenerate it: ricochet-server --print-config > server/config/ricochet.toml";
  ServerConfig loaded;
  EXPECT_TRUE(apply_config_toml(text.str(), sample.string(), loaded).empty());
}

}  // namespace
}  // namespace ricochet::server::config_test
