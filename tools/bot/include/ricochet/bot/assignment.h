#pragma once
/// Placement as the bot follows it (PROTOCOL.md, Placement): what `--find-match MODE[:MAP]` asks
/// for, and the server's Assignment checked before the bot acts on it. Sans-IO: the time the
/// reply arrived is a parameter.
///
/// The Assignment is read as untrusted bytes (every field checked, a bad one refuses the whole
/// reply) even though it came over a control channel whose certificate the bot already trusted:
/// a bug on the server must not send the bot to a port 0 or pin an empty fingerprint.

#include <boost/asio/ip/address.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "ricochet/proto/clock.h"
#include "ricochet/wire/control.pb.h"

namespace ricochet::bot {

/// What a bot asks find_match for.
struct MatchWanted {
  std::string mode;  ///< 1..32 of [a-z0-9_-]
  std::string map;   ///< empty: any; else 1..64 of [A-Za-z0-9_.-]
};

/// "MODE" or "MODE:MAP" as PROTOCOL.md's find_match takes them; otherwise why not, with the
/// rule.
std::variant<MatchWanted, std::string> parse_match_wanted(std::string_view text);

/// An Assignment the bot can follow.
struct Assigned {
  bool on_this_server = false;  ///< join here with the ticket; the fields below are unused
  /// The assigned server's control channel (a numeric address: the bot resolves no names).
  boost::asio::ip::address host;
  std::uint16_t control_port = 0;
  std::uint16_t game_port = 0;  ///< its game channel, on `host`
  /// Its certificate's SHA-256 in ServerTrust's canonical form ("AB:CD:..."), to pin.
  std::string fingerprint;
  std::uint32_t match_id = 0;  ///< 0: a new match is made there
  std::string ticket;          ///< 32 bytes, for JoinMatchRequest.ticket
  /// Until when (the bot's clock) the ticket may be presented.
  proto::TimeUs ticket_expires_at_us = 0;

  bool ticket_usable(proto::TimeUs now) const { return now < ticket_expires_at_us; }
  /// Seconds the ticket has left at `now` (0 once expired).
  double ticket_left_s(proto::TimeUs now) const;
};

/// The assignment of a FindMatchReply received at `now` (the bot's clock), checked: the ticket
/// 32 bytes, and unless on_this_server the connection "IPv4:port" or "[IPv6]:port" with a port
/// 1..65535, the game port 1..65535 and the fingerprint 64 hex digits. Otherwise what is wrong.
std::variant<Assigned, std::string> read_assignment(const wire::Assignment& assignment,
                                                    proto::TimeUs now);

}  // namespace ricochet::bot
