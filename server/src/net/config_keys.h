#pragma once
/// The one table of configuration keys: section, name, flag, description, kind and allowed range.
/// The TOML loader, the command line, validate() and the rendered sample all walk it, so a key
/// added here is loadable, overridable, documented and checked at once.

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ricochet/server/config.h"

namespace ricochet::server::config_keys {

enum class Kind {
  Integer,   ///< an int within [min, max]
  Text,      ///< a string; non-empty unless allow_empty
  Address,   ///< an IP address literal (IPv4 or IPv6)
  Choice,    ///< one of `choices` (separated by '|')
  Number,    ///< a double within [min_number, max_number]; TOML takes a float or an integer
  Bool,      ///< true or false
  TextList,  ///< one or more non-empty strings; a TOML array, a comma-separated flag
};

struct Key {
  std::string_view section{};  ///< TOML table, e.g. "game"
  std::string_view name{};     ///< key within it, e.g. "tick_rate_hz"
  std::string_view flag{};     ///< command-line flag, e.g. "--tick-rate-hz"
  std::string_view help{};     ///< one line; the range or choices are appended where shown
  Kind kind = Kind::Integer;
  int& (*integer)(ServerConfig&) = nullptr;  ///< Integer
  int min = 0;
  int max = 0;
  std::string& (*text)(ServerConfig&) = nullptr;  ///< Text, Address
  bool allow_empty = false;
  std::string_view choices{};                                     ///< Choice: "a|b|c"
  std::string_view (*get_choice)(const ServerConfig&) = nullptr;  ///< Choice
  bool (*set_choice)(ServerConfig&, std::string_view) = nullptr;  ///< Choice; false: not a choice
  double& (*number)(ServerConfig&) = nullptr;                     ///< Number
  double min_number = 0;
  double max_number = 0;
  bool& (*boolean)(ServerConfig&) = nullptr;                    ///< Bool
  std::vector<std::string>& (*texts)(ServerConfig&) = nullptr;  ///< TextList

  /// "game.tick_rate_hz"
  std::string full_name() const;
};

/// Every key, in the order of the sample file and --help.
std::span<const Key> all();
/// The key named "section.name", or nullptr.
const Key* find(std::string_view section, std::string_view name);
/// The sections in order ("server", "db", ...), each once.
std::span<const std::string_view> sections();

/// The key's current value as text: integers in decimal, numbers in their shortest exact form,
/// true/false, strings and choices as they are, lists comma-separated.
std::string value_text(const Key& key, const ServerConfig& config);
/// The key's current value as a TOML value: a number, a boolean, a quoted string or an array.
std::string value_toml(const Key& key, const ServerConfig& config);
/// "10..128", "0..1.5", "true or false", "one of text|json", "an IP address", "non-empty",
/// "any text" or "one or more non-empty".
std::string allowed_text(const Key& key);
/// The range problem of the key's current value, or empty: "game.tick_rate_hz must be 10..128,
/// got 0".
std::string check(const Key& key, const ServerConfig& config);
/// Parses `text` as the key's value (a command-line argument; a list comma-separated) into
/// config; returns the problem or empty. Range checks are left to check().
std::string assign_text(const Key& key, std::string_view text, ServerConfig& config);

}  // namespace ricochet::server::config_keys
