/// MatchConfig: validation, and the exact text codec recordings carry (match_config.h).

#include "ricochet/server/match_config.h"

#include <charconv>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>

#include "range_check.h"

namespace ricochet::server {

namespace {

/// One field of the codec: its key, how to print it and how to read it back.
struct Field {
  std::string key;
  std::function<std::string()> print;
  std::function<bool(std::string_view)> read;
};

std::string print_float(float value) {
  char text[48];
  std::snprintf(text, sizeof text, "%a", static_cast<double>(value));
  return text;
}

bool read_float(std::string_view text, float& out) {
  const std::string copy(text);
  char* end = nullptr;
  const float value = std::strtof(copy.c_str(), &end);
  if (copy.empty() || end != copy.c_str() + copy.size() || !std::isfinite(value)) return false;
  out = value;
  return true;
}

template <typename Int>
bool read_int(std::string_view text, Int& out) {
  Int value{};
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return false;
  out = value;
  return true;
}

template <typename Int>
Field int_field(std::string key, Int& value) {
  return {std::move(key), [&value] { return std::to_string(value); },
          [&value](std::string_view text) { return read_int(text, value); }};
}

Field float_field(std::string key, float& value) {
  return {std::move(key), [&value] { return print_float(value); },
          [&value](std::string_view text) { return read_float(text, value); }};
}

Field bool_field(std::string key, bool& value) {
  return {std::move(key), [&value] { return std::string(value ? "1" : "0"); },
          [&value](std::string_view text) {
            if (text != "0" && text != "1") return false;
            value = text == "1";
            return true;
          }};
}

/// Names may hold spaces but not line breaks (validate() refuses control characters).
Field text_field(std::string key, std::string& value) {
  return {std::move(key), [&value] { return value; },
          [&value](std::string_view text) {
            value = std::string(text);
            return true;
          }};
}

/// The one table both directions use: every field of `config`, by key.
std::vector<Field> fields_of(MatchConfig& config) {
  std::vector<Field> f;
  f.push_back(int_field("id", config.id));
  f.push_back(text_field("name", config.name));
  f.push_back(int_field("max_players", config.max_players));
  f.push_back(int_field("tick.rate_hz", config.tick.rate_hz));
  f.push_back(int_field("tick.max_catch_up_steps", config.tick.max_catch_up_steps));
  f.push_back(int_field("snapshot_rate_hz", config.snapshot_rate_hz));
  f.push_back(int_field("snapshot_budget_bytes", config.snapshot_budget_bytes));
  f.push_back(int_field("reconnect_grace_us", config.reconnect_grace_us));
  f.push_back(int_field("history_ticks", config.history_ticks));
  MovementConfig& m = config.movement;
  f.push_back(float_field("movement.max_speed_mps", m.max_speed_mps));
  f.push_back(float_field("movement.ground_acceleration", m.ground_acceleration));
  f.push_back(float_field("movement.air_acceleration", m.air_acceleration));
  f.push_back(float_field("movement.friction", m.friction));
  f.push_back(float_field("movement.stop_speed_mps", m.stop_speed_mps));
  f.push_back(float_field("movement.jump_speed_mps", m.jump_speed_mps));
  f.push_back(float_field("movement.ground_max_slope_deg", m.ground_max_slope_deg));
  f.push_back(float_field("movement.ground_probe_m", m.ground_probe_m));
  f.push_back(int_field("input.max_depth", config.input.max_depth));
  proto::QuantizationSpec& q = config.quantization;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const std::string suffix(1, "xyz"[axis]);
    f.push_back(float_field("quantization.min_m." + suffix, q.bounds.min_m[axis]));
    f.push_back(float_field("quantization.max_m." + suffix, q.bounds.max_m[axis]));
  }
  f.push_back(float_field("quantization.position_step_m", q.position_step_m));
  f.push_back(float_field("quantization.velocity_step_mps", q.velocity_step_mps));
  f.push_back(float_field("quantization.max_speed_mps", q.max_speed_mps));
  f.push_back(int_field("quantization.orientation_bits", q.orientation_bits));
  f.push_back(float_field("quantization.tick_s", q.tick_s));
  RulesConfig& r = config.rules;
  f.push_back({"rules.mode", [&r] { return std::string(name(r.mode)); },
               [&r](std::string_view text) {
                 if (text == "ffa")
                   r.mode = GameMode::FreeForAll;
                 else if (text == "tdm")
                   r.mode = GameMode::TeamDeathmatch;
                 else
                   return false;
                 return true;
               }});
  f.push_back(int_field("rules.min_players", r.min_players));
  f.push_back(float_field("rules.warmup_s", r.warmup_s));
  f.push_back(int_field("rules.frag_limit", r.frag_limit));
  f.push_back(float_field("rules.time_limit_s", r.time_limit_s));
  f.push_back(float_field("rules.respawn_delay_s", r.respawn_delay_s));
  f.push_back(float_field("rules.spawn_protection_s", r.spawn_protection_s));
  f.push_back(int_field("rules.seed", r.seed));
  WeaponsConfig& w = config.weapons;
  static constexpr const char* kWeaponKeys[kWeaponCount] = {"rifle", "rocket", "grenade"};
  for (std::size_t k = 0; k < kWeaponCount; ++k) {
    WeaponConfig& c = w.weapons[k];
    const std::string p = std::string("weapons.") + kWeaponKeys[k] + ".";
    f.push_back(float_field(p + "fire_interval_s", c.fire_interval_s));
    f.push_back(int_field(p + "damage", c.damage));
    f.push_back(float_field(p + "range_m", c.range_m));
    f.push_back(float_field(p + "spread_rad", c.spread_rad));
    f.push_back(int_field(p + "ammo_start", c.ammo_start));
    f.push_back(int_field(p + "ammo_max", c.ammo_max));
    f.push_back(int_field(p + "ammo_per_pickup", c.ammo_per_pickup));
    f.push_back(float_field(p + "projectile_speed_mps", c.projectile_speed_mps));
    f.push_back(float_field(p + "projectile_radius_m", c.projectile_radius_m));
    f.push_back(float_field(p + "gravity_scale", c.gravity_scale));
    f.push_back(float_field(p + "restitution", c.restitution));
    f.push_back(float_field(p + "fuse_s", c.fuse_s));
    f.push_back(float_field(p + "explosion_radius_m", c.explosion_radius_m));
    f.push_back(float_field(p + "explosion_impulse_ns", c.explosion_impulse_ns));
  }
  f.push_back(float_field("weapons.self_damage_scale", w.self_damage_scale));
  f.push_back(bool_field("weapons.friendly_fire", w.friendly_fire));
  f.push_back(float_field("weapons.friendly_fire_scale", w.friendly_fire_scale));
  f.push_back(float_field("weapons.armor_absorb", w.armor_absorb));
  f.push_back(float_field("weapons.max_turn_rate_rad_s", w.max_turn_rate_rad_s));
  LagCompensationConfig& l = config.lag;
  f.push_back(float_field("lag.history_s", l.history_s));
  f.push_back(float_field("lag.max_rewind_ms", l.max_rewind_ms));
  f.push_back(float_field("lag.claim_tolerance_ms", l.claim_tolerance_ms));
  f.push_back(float_field("lag.interpolation_delay_ms", l.interpolation_delay_ms));
  f.push_back(bool_field("lag.enabled", l.enabled));
  f.push_back(bool_field("record", config.record));
  f.push_back(int_field("hash_interval_ticks", config.hash_interval_ticks));
  f.push_back(int_field("max_recording_bytes", config.max_recording_bytes));
  return f;
}

}  // namespace

bool is_printable_utf8(std::string_view text) {
  std::size_t at = 0;
  while (at < text.size()) {
    const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[at + k]); };
    const unsigned char lead = byte(0);
    std::size_t length = 0;
    std::uint32_t code = 0;
    if (lead < 0x80) {
      length = 1;
      code = lead;
    } else if (lead >= 0xC2 && lead <= 0xDF) {
      length = 2;
      code = lead & 0x1Fu;
    } else if (lead >= 0xE0 && lead <= 0xEF) {
      length = 3;
      code = lead & 0x0Fu;
    } else if (lead >= 0xF0 && lead <= 0xF4) {
      length = 4;
      code = lead & 0x07u;
    } else {
      return false;
    }
    if (at + length > text.size()) return false;
    for (std::size_t k = 1; k < length; ++k) {
      if ((byte(k) & 0xC0u) != 0x80u) return false;
      code = (code << 6) | (byte(k) & 0x3Fu);
    }
    const std::uint32_t smallest[] = {0, 0, 0x80, 0x800, 0x10000};
    if (code < smallest[length] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) {
      return false;
    }
    if (code < 0x20 || (code >= 0x7F && code < 0xA0)) return false;
    at += length;
  }
  return true;
}

std::string MatchConfig::validate() const {
  if (name.empty() || name.size() > 32 || !is_printable_utf8(name)) {
    return "match name must be 1..32 bytes of printable UTF-8, got '" + name + "'";
  }
  if (max_players < 1 || max_players > 64) {
    return range_error("match", "max_players", "1..64", static_cast<long long>(max_players));
  }
  if (std::string error = tick.validate(); !error.empty()) return "match " + error;
  if (snapshot_rate_hz < 1 || snapshot_rate_hz > tick.rate_hz) {
    return "match snapshot_rate_hz must be 1..tick rate_hz (" + std::to_string(tick.rate_hz) +
           "), got " + std::to_string(snapshot_rate_hz);
  }
  if (snapshot_budget_bytes < 192 || snapshot_budget_bytes > 1100) {
    return range_error("match", "snapshot_budget_bytes", "192..1100",
                       static_cast<long long>(snapshot_budget_bytes));
  }
  if (reconnect_grace_us < 0 || reconnect_grace_us > 300 * proto::kMicrosPerSecond) {
    return range_error("match", "reconnect_grace_us", "0..300000000",
                       static_cast<long long>(reconnect_grace_us));
  }
  if (history_ticks < 1 || history_ticks > 1024) {
    return range_error("match", "history_ticks", "1..1024", static_cast<long long>(history_ticks));
  }
  if (std::string error = movement.validate(); !error.empty()) return "match " + error;
  if (std::string error = input.validate(); !error.empty()) return "match " + error;
  if (std::string error = rules.validate(); !error.empty()) return error;
  if (std::string error = weapons.validate(); !error.empty()) return "match " + error;
  if (std::string error = lag.validate(); !error.empty()) return "match " + error;
  if (hash_interval_ticks < 1 || hash_interval_ticks > 3600) {
    return range_error("match", "hash_interval_ticks", "1..3600",
                       static_cast<long long>(hash_interval_ticks));
  }
  if (max_recording_bytes < 4096 || max_recording_bytes > (std::size_t{1} << 30)) {
    return range_error("match", "max_recording_bytes", "4096..1073741824",
                       static_cast<long long>(max_recording_bytes));
  }
  return {};
}

std::vector<std::uint8_t> encode_match_config(const MatchConfig& config) {
  MatchConfig copy = config;
  std::string text = "ricochet-match-config 1\n";
  for (const Field& field : fields_of(copy)) {
    text += field.key;
    text += ' ';
    text += field.print();
    text += '\n';
  }
  return {text.begin(), text.end()};
}

std::variant<MatchConfig, std::string> decode_match_config(std::span<const std::uint8_t> bytes) {
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  constexpr std::string_view kMagic = "ricochet-match-config 1\n";
  if (!text.starts_with(kMagic))
    return std::string("match config: expected 'ricochet-match-config 1'");
  MatchConfig config;
  std::vector<Field> fields = fields_of(config);
  std::map<std::string, Field*, std::less<>> by_key;
  for (Field& field : fields) by_key.emplace(field.key, &field);
  std::size_t at = kMagic.size();
  std::size_t line = 1;
  std::map<std::string, bool, std::less<>> seen;
  while (at < text.size()) {
    ++line;
    const std::size_t end = text.find('\n', at);
    if (end == std::string_view::npos) {
      return "match config line " + std::to_string(line) + ": no line end";
    }
    const std::string_view entry = text.substr(at, end - at);
    at = end + 1;
    const std::size_t space = entry.find(' ');
    const std::string_view key = entry.substr(0, space);
    const auto found = by_key.find(key);
    if (space == std::string_view::npos || found == by_key.end()) {
      return "match config line " + std::to_string(line) + ": unknown key '" + std::string(key) +
             "'";
    }
    if (!seen.emplace(std::string(key), true).second) {
      return "match config: key '" + std::string(key) + "' twice";
    }
    if (!found->second->read(entry.substr(space + 1))) {
      return "match config: bad value for '" + std::string(key) + "'";
    }
  }
  if (seen.size() != fields.size()) return std::string("match config: keys are missing");
  if (std::string error = config.validate(); !error.empty()) return "match config: " + error;
  return config;
}

}  // namespace ricochet::server
