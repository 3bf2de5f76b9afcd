#include "ricochet/server/config.h"

#include <toml++/toml.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <thread>

#include "config_keys.h"
#include "ricochet/db/store.h"

namespace ricochet::server {
namespace {

namespace keys = config_keys;

constexpr int kUsageExitCode = 2;

std::string join_lines(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) {
    text += line;
    text += '\n';
  }
  return text;
}

const char* type_name(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::none:
      return "nothing";
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a float";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::date:
      return "a date";
    case toml::node_type::time:
      return "a time";
    case toml::node_type::date_time:
      return "a date-time";
  }
  return "a value";
}

/// "ricochet.toml:3:1: "
std::string location(std::string_view source_name, const toml::source_region& region) {
  std::string text{source_name};
  text += ':' + std::to_string(region.begin.line) + ':' + std::to_string(region.begin.column);
  return text + ": ";
}

std::string known_keys_of(std::string_view section) {
  std::string known;
  for (const keys::Key& key : keys::all()) {
    if (key.section != section) continue;
    if (!known.empty()) known += ", ";
    known += key.name;
  }
  return known;
}

std::string known_sections() {
  std::string known;
  for (std::string_view section : keys::sections()) {
    if (!known.empty()) known += ", ";
    known += section;
  }
  return known;
}

/// Assigns one TOML value to its key; returns the problem or empty.
std::string apply_value(const keys::Key& key, const toml::node& node, ServerConfig& config) {
  const std::string full = key.full_name();
  switch (key.kind) {
    case keys::Kind::Integer: {
      const auto* integer = node.as_integer();
      if (integer == nullptr) {
        return full + " must be an integer " + keys::allowed_text(key) + ", got " + type_name(node);
      }
      const std::int64_t value = integer->get();
      if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max()) {
        return full + " must be " + keys::allowed_text(key) + ", got " + std::to_string(value);
      }
      key.integer(config) = static_cast<int>(value);
      return {};
    }
    case keys::Kind::Number: {
      const std::optional<double> value = node.value<double>();  // a float or an integer
      if (!value || !(node.is_floating_point() || node.is_integer())) {
        return full + " must be a number " + keys::allowed_text(key) + ", got " + type_name(node);
      }
      key.number(config) = *value;
      return {};
    }
    case keys::Kind::Bool: {
      const auto* boolean = node.as_boolean();
      if (boolean == nullptr) return full + " must be true or false, got " + type_name(node);
      key.boolean(config) = boolean->get();
      return {};
    }
    case keys::Kind::TextList: {
      const auto* array = node.as_array();
      if (array == nullptr) {
        return full + " must be an array of strings, " + keys::allowed_text(key) + ", got " +
               type_name(node);
      }
      std::vector<std::string> texts;
      for (const toml::node& item : *array) {
        const auto* text = item.as_string();
        if (text == nullptr) {
          return full + " must be an array of strings, got " + type_name(item) + " in it";
        }
        texts.push_back(text->get());
      }
      key.texts(config) = std::move(texts);
      return {};
    }
    case keys::Kind::Text:
    case keys::Kind::Address:
    case keys::Kind::Choice:
      break;
  }
  const auto* text = node.as_string();
  if (text == nullptr) {
    return full + " must be a string, " + keys::allowed_text(key) + ", got " + type_name(node);
  }
  return keys::assign_text(key, text->get(), config);
}

/// Whether --help and the sample show the key's range after its description.
bool shows_range(const keys::Key& key) {
  return key.kind == keys::Kind::Integer || key.kind == keys::Kind::Number ||
         key.kind == keys::Kind::Choice;
}

}  // namespace

std::vector<std::string> ServerConfig::validate() const {
  std::vector<std::string> problems;
  for (const keys::Key& key : keys::all()) {
    std::string problem = keys::check(key, *this);
    if (!problem.empty()) problems.push_back(std::move(problem));
  }
  if (!db.url.empty() && !db::is_postgres_url(db.url)) {
    // Only the scheme: the rest may hold a password.
    problems.push_back("db.url must start with postgresql:// or postgres://, got '" +
                       db.url.substr(0, db.url.find(':')) + ":…'");
  }
  if (placement.server_ttl_s < 2 * placement.heartbeat_s) {
    problems.push_back("placement.server_ttl_s must be at least twice placement.heartbeat_s (" +
                       std::to_string(2 * placement.heartbeat_s) + "), got " +
                       std::to_string(placement.server_ttl_s));
  }
  if (dashboard.max_replays < dashboard.replay_workers) {
    problems.push_back("dashboard.max_replays must be at least dashboard.replay_workers (" +
                       std::to_string(dashboard.replay_workers) + "), got " +
                       std::to_string(dashboard.max_replays));
  }
  if (game.snapshot_rate_hz > game.tick_rate_hz) {
    problems.push_back("game.snapshot_rate_hz must be 0..game.tick_rate_hz (" +
                       std::to_string(game.tick_rate_hz) + "; 0: the tick rate), got " +
                       std::to_string(game.snapshot_rate_hz));
  }
  if (!snapshot_cache_layers()) {
    problems.push_back(
        "game.snapshot_cache_off must list streams, deltas, world_baselines, walks, "
        "whole_world_start or all, comma-separated, got \"" +
        game.snapshot_cache_off + "\"");
  }
  if (tls.cert_file.empty() != tls.key_file.empty()) {
    problems.push_back(
        "tls.cert_file and tls.key_file must be both set or both empty, got cert_file \"" +
        tls.cert_file + "\" and key_file \"" + tls.key_file + "\"");
  }
  if (control.port != 0 && control.port == admin.port) {
    problems.push_back("admin.port must differ from control.port (both are TCP), got " +
                       std::to_string(admin.port) + " for both");
  }
  if (matches.min_players > matches.max_players) {
    problems.push_back("matches.min_players must be 1..matches.max_players (" +
                       std::to_string(matches.max_players) + "), got " +
                       std::to_string(matches.min_players));
  }
  if (control.max_connections_per_address > control.max_connections) {
    problems.push_back("control.max_connections_per_address must be 1..control.max_connections (" +
                       std::to_string(control.max_connections) + "), got " +
                       std::to_string(control.max_connections_per_address));
  }
  if (matches.max_created_per_account > matches.max_created) {
    problems.push_back("matches.max_created_per_account must be 0..matches.max_created (" +
                       std::to_string(matches.max_created) + "), got " +
                       std::to_string(matches.max_created_per_account));
  }
  if (admin.max_connections_per_address > admin.max_connections) {
    problems.push_back("admin.max_connections_per_address must be 1..admin.max_connections (" +
                       std::to_string(admin.max_connections) + "), got " +
                       std::to_string(admin.max_connections_per_address));
  }
  if (admin.max_streams_per_address > admin.max_connections) {
    problems.push_back("admin.max_streams_per_address must be 1..admin.max_connections (" +
                       std::to_string(admin.max_connections) + "), got " +
                       std::to_string(admin.max_streams_per_address));
  }
  const int rate = snapshot_rate_hz();
  if (rate > 0 && game.bandwidth_kbps_per_client * 125 < kMinSnapshotBytes * rate) {
    const int least_kbps = (kMinSnapshotBytes * rate + 124) / 125;
    problems.push_back(
        "game.bandwidth_kbps_per_client must be at least " + std::to_string(least_kbps) + " at " +
        std::to_string(rate) + " snapshots/s (" + std::to_string(kMinSnapshotBytes) +
        " bytes per snapshot), got " + std::to_string(game.bandwidth_kbps_per_client));
  }
  return problems;
}

int ServerConfig::snapshot_budget_bytes() const {
  const long long bytes_per_second = static_cast<long long>(game.bandwidth_kbps_per_client) * 125;
  const long long per_snapshot = bytes_per_second / std::max(1, snapshot_rate_hz());
  return static_cast<int>(std::min<long long>(per_snapshot, kMaxSnapshotBytes));
}

int ServerConfig::worker_threads() const {
  if (server.threads > 0) return server.threads;
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

std::optional<proto::SnapshotCacheLayers> ServerConfig::snapshot_cache_layers() const {
  proto::SnapshotCacheLayers layers;
  if (game.snapshot_cache_off.empty()) return layers;
  std::string_view rest = game.snapshot_cache_off;
  for (;;) {
    const std::size_t comma = rest.find(',');
    if (!proto::switch_off_cache_layer(rest.substr(0, comma), layers)) return std::nullopt;
    if (comma == std::string_view::npos) return layers;
    rest.remove_prefix(comma + 1);
  }
}

int ServerConfig::snapshot_rate_hz() const {
  return game.snapshot_rate_hz == 0 ? game.tick_rate_hz : game.snapshot_rate_hz;
}

namespace {
/// `path` itself when absolute, else under data_dir.
std::string under_data_dir(const ProcessConfig& server, const std::string& path) {
  if (std::filesystem::path{path}.is_absolute()) return path;
  return (std::filesystem::path{server.data_dir} / path).string();
}
}  // namespace

std::string ServerConfig::db_file() const {
  return under_data_dir(server, db.path);
}

std::string ServerConfig::db_url_or_path() const {
  return db.url.empty() ? db_file() : db.url;
}

std::string ServerConfig::outbox_path() const {
  return under_data_dir(server, db.outbox_dir);
}

bool PlacementConfig::on(const DbConfig& db) const {
  if (enabled == PlacementMode::Auto) return !db.url.empty();
  return enabled == PlacementMode::On;
}

std::string ServerConfig::recordings_path() const {
  return under_data_dir(server, matches.recordings_dir);
}

std::string ServerConfig::ports_file_path() const {
  return server.ports_file.empty() ? std::string{} : under_data_dir(server, server.ports_file);
}

std::vector<std::string> apply_config_toml(std::string_view toml_text, std::string_view source_name,
                                           ServerConfig& config) {
  std::vector<std::string> problems;
  toml::table root;
  try {
    root = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& error) {
    problems.push_back(location(source_name, error.source()) +
                       "malformed TOML: " + std::string{error.description()});
    return problems;
  }
  for (auto&& [section_key, section_node] : root) {
    const std::string_view section = section_key.str();
    const auto& sections = keys::sections();
    if (std::find(sections.begin(), sections.end(), section) == sections.end()) {
      problems.push_back(location(source_name, section_node.source()) + "unknown key '" +
                         std::string{section} + "' (known tables: " + known_sections() + ")");
      continue;
    }
    const auto* table = section_node.as_table();
    if (table == nullptr) {
      problems.push_back(location(source_name, section_node.source()) + "'" + std::string{section} +
                         "' must be a table ([" + std::string{section} + "]), got " +
                         type_name(section_node));
      continue;
    }
    for (auto&& [name_key, value] : *table) {
      const keys::Key* key = keys::find(section, name_key.str());
      if (key == nullptr) {
        problems.push_back(location(source_name, value.source()) + "unknown key '" +
                           std::string{section} + "." + std::string{name_key.str()} +
                           "' (known keys in [" + std::string{section} +
                           "]: " + known_keys_of(section) + ")");
        continue;
      }
      std::string problem = apply_value(*key, value, config);
      if (!problem.empty()) problems.push_back(location(source_name, value.source()) + problem);
    }
  }
  return problems;
}

std::vector<std::string> apply_config_file(const std::string& path, ServerConfig& config) {
  std::error_code status_error;
  if (std::filesystem::is_directory(path, status_error)) {
    return {"cannot read config file \"" + path + "\": it is a directory"};
  }
  std::ifstream file{path, std::ios::binary};
  std::ostringstream text;
  if (file) text << file.rdbuf();
  if (!file || file.bad()) {
    return {"cannot read config file \"" + path +
            "\": " + std::error_code{errno, std::generic_category()}.message()};
  }
  return apply_config_toml(text.str(), path, config);
}

std::string render_config_toml(const ServerConfig& config) {
  std::string out =
      "# Ricochet server configuration: every key with its default value.\n"
      "# Load it with `ricochet-server --config FILE`; a flag given on the command line overrides\n"
      "# the file (see `ricochet-server --help`). Unknown keys are errors.\n";
  for (std::string_view section : keys::sections()) {
    out += "\n[";
    out += section;
    out += "]\n";
    for (const keys::Key& key : keys::all()) {
      if (key.section != section) continue;
      out += "# ";
      out += key.help;
      if (shows_range(key)) out += " (" + keys::allowed_text(key) + ")";
      out += "; flag ";
      out += key.flag;
      if (key.kind == keys::Kind::TextList) out += " (comma-separated)";
      out += '\n';
      out += key.name;
      out += " = ";
      out += keys::value_toml(key, config);
      out += '\n';
    }
  }
  return out;
}

ParseOutcome parse_command_line(int argc, const char* const* argv) {
  CLI::App app{"Ricochet game server: TLS control channel, encrypted UDP game channel, admin HTTP.",
               "ricochet-server"};
  app.set_version_flag("--version", std::string{"ricochet-server "} + RICOCHET_VERSION);
  std::string config_path;
  app.add_option("--config", config_path,
                 "TOML file applied over the defaults; flags override it (sample: "
                 "server/config/ricochet.toml)")
      ->type_name("PATH");
  bool print_config = false;
  app.add_flag("--print-config", print_config,
               "print the effective configuration as TOML and exit");

  /// Flags in the order given; applied after the file.
  std::vector<std::pair<const keys::Key*, std::string>> overrides;
  const ServerConfig defaults;
  for (const keys::Key& key : keys::all()) {
    std::string help{key.help};
    if (shows_range(key)) help += " (" + keys::allowed_text(key) + ")";
    help += "; TOML " + key.full_name();
    const char* type = key.kind == keys::Kind::Integer    ? "INT"
                       : key.kind == keys::Kind::Number   ? "NUMBER"
                       : key.kind == keys::Kind::Bool     ? "BOOL"
                       : key.kind == keys::Kind::Address  ? "ADDRESS"
                       : key.kind == keys::Kind::Choice   ? "CHOICE"
                       : key.kind == keys::Kind::TextList ? "LIST"
                                                          : "TEXT";
    const std::string default_value = keys::value_text(key, defaults);
    app.add_option_function<std::string>(
           std::string{key.flag},
           [&overrides, &key](const std::string& value) { overrides.emplace_back(&key, value); },
           help)
        ->type_name(type)
        ->default_str(default_value.empty() ? "\"\"" : default_value)
        ->group("[" + std::string{key.section} + "]");
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    std::ostringstream out;
    std::ostringstream err;
    const int code = app.exit(error, out, err);
    return {std::nullopt, code == 0 ? 0 : kUsageExitCode, out.str() + err.str()};
  }

  ServerConfig config;
  std::vector<std::string> problems;
  if (!config_path.empty()) problems = apply_config_file(config_path, config);
  for (const auto& [key, value] : overrides) {
    std::string problem = keys::assign_text(*key, value, config);
    if (!problem.empty()) problems.push_back(std::string{key->flag} + ": " + problem);
  }
  if (problems.empty()) problems = config.validate();
  if (!problems.empty()) {
    return {std::nullopt, kUsageExitCode,
            "ricochet-server: invalid configuration\n" + join_lines(problems) +
                "Run with --help for every option and its default.\n"};
  }
  if (print_config) return {std::nullopt, 0, render_config_toml(config)};
  return {std::move(config), 0, {}};
}

}  // namespace ricochet::server
