#pragma once
/// What one bot is told: where the server is, how to trust it, who to be, which match to join
/// and how to play. Defaults are usable against a local server; validate() explains what is wrong.

#include <cstdint>
#include <string>

#include "ricochet/bot/link_simulator.h"

namespace ricochet::bot {

struct BotConfig {
  /// The server's IP address (numeric IPv4 or IPv6); the game channel is on the same host.
  std::string host = "127.0.0.1";
  std::uint16_t control_port = 7777;  ///< TLS control channel, TCP
  /// Local address both channels' sockets bind to (numeric, of the server's family); empty: the
  /// system's choice. Load tests spread bots over 127.0.0.x so each address stays within the
  /// server's per-address limits.
  std::string bind_address;
  /// 0: input ticks count from the game connection's start; N (1..64): each tick falls on phase
  /// seed % N of a tick-rate grid on the steady clock, shared by every bot of the process, so
  /// that a thousand bots wake their loop N times per tick instead of a thousand.
  int tick_phases = 0;
  /// Pinned certificate SHA-256 fingerprint ("AA:BB:...", 32 pairs); empty: trust_file decides.
  std::string fingerprint;
  /// Trust on first use: the file is created with the first fingerprint seen; a later mismatch
  /// refuses the server. Used when fingerprint is empty.
  std::string trust_file;
  std::string name = "bot";               ///< account name, 3..24 of [A-Za-z0-9_.-]
  std::string password = "ricochet-bot";  ///< 8..1024 bytes; the account is registered if new
  std::uint32_t match_id = 0;             ///< 0: the first listed match with room
  /// "MODE" or "MODE:MAP" (assignment.h): ask the server for a seat with find_match and follow
  /// the Assignment, to another server of the fleet if it says so; after each match, ask again
  /// through this server (host). Empty: list the matches (or join match_id) here.
  std::string find_match;
  double skill = 0.5;      ///< 0..1: 1 aims exactly, 0 with the largest aim error
  std::uint64_t seed = 1;  ///< the behaviour's random numbers
  /// The game channel's simulated link, each direction (seeded from `seed`); inactive: none.
  LinkConfig link;
  /// s of game connection after which the bot moves to a new local port (an address change)
  /// and reconnects with a fresh token; 0: never.
  double rebind_after_s = 0;
  int matches = 0;  ///< matches to finish (MatchResults received) before stopping; 0: no limit
  int max_reconnect_attempts = 5;  ///< failed reconnects in a row before giving up, 1..1000
  bool predict = true;  ///< false: cheap mode, no prediction or interpolation (load tests)
  /// A CSV file of every decoded snapshot's players (state_dump.h); empty: none. A fleet of N
  /// bots gives bot k the file `<dump_states>-k`.
  std::string dump_states;

  /// Empty when usable; otherwise the first wrong field, its allowed range and its value.
  std::string validate() const;
};

/// An account name the server takes: 3..24 characters of [A-Za-z0-9_.-].
bool valid_account_name(const std::string& name);

}  // namespace ricochet::bot
