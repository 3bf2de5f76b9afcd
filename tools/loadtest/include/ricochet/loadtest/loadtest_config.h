#pragma once
/// What one load test is told: the servers, how many bots and how fast they come, how long to
/// measure, where to write. validate() explains what is wrong.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace ricochet::loadtest {

/// Whether the load test reads a server's /proc entry as well as its /metrics.
enum class ServerProc : std::uint8_t {
  Off,   ///< never: /metrics only (a server on another host, or in its own namespace)
  Auto,  ///< when the server is on loopback and its pid's entry reads; given up at the first miss
};
/// "off", "auto".
const char* name(ServerProc mode);
/// "off" | "auto" → the mode; nullopt otherwise.
std::optional<ServerProc> parse_server_proc(std::string_view text);

/// One server under test.
struct ServerEndpoint {
  /// Numeric IPv4. On loopback (127.0.0.0/8) the bots spread over loopback source addresses and
  /// share one game socket; elsewhere each bot has its own sockets from the default address.
  std::string host = "127.0.0.1";
  std::uint16_t control_port = 7777;  ///< TLS control channel
  /// Admin HTTP (/metrics), on the same address; 0: none known (a --fleet row that advertises
  /// none): never scraped, its CPU and RSS unknown.
  std::uint16_t admin_port = 9100;
  std::string fingerprint;  ///< pinned certificate fingerprint; empty: trust_file
  std::string trust_file;   ///< trust on first use (main: DIR/server.fp, -2.fp, ...)
  /// Sent as `Authorization: Bearer <admin_token>` on every /metrics scrape (the server's
  /// admin.token_file); empty: no header.
  std::string admin_token;

  /// "host:control_port", the server's name in reports.
  std::string label() const;
};

inline constexpr std::size_t kMaxServers = 64;

struct LoadTestConfig {
  /// 1..kMaxServers servers; the bots go round robin over them (bot k to server k % size), or
  /// all to the first with find_match, and every one is scraped.
  std::vector<ServerEndpoint> servers{ServerEndpoint{}};
  /// "MODE" or "MODE:MAP" (bot::parse_match_wanted): every bot goes to the first server, asks it
  /// for a seat (find_match) and plays where the assignment sends it; empty: round robin, each
  /// bot joining a listed match on its server.
  std::string find_match;
  int bots = 16;             ///< 1..10000 (the largest step with --sweep), over all servers
  std::vector<int> sweep;    ///< increasing bot counts; empty: one run of `bots`
  int match_size = 16;       ///< 1..64 players per match the server is expected to host
  double duration_s = 60;    ///< measured, after the ramp (each step with --sweep)
  double ramp_per_s = 50;    ///< bots started per second, 0.1..1000
  double settle_s = 5;       ///< after the last start, before measuring, 0..600
  int bots_per_address = 8;  ///< bots per loopback source address, 1..16
  bool cheap = true;         ///< bots skip prediction and interpolation
  /// Every bot's game channel on one UDP socket (bot::SharedGamePort: a loopback source address
  /// per connection, sendmmsg/recvmmsg); false: a socket per bot.
  bool shared_game_port = true;
  double skill = 0.5;         ///< 0..1
  std::string name = "load";  ///< account prefix, 1..12 of [A-Za-z0-9_.-]
  std::string password = "ricochet-load";
  double scrape_interval_s = 1;  ///< /metrics and /proc, 0.2..60
  int server_pid = 0;            ///< 0: read ricochet_process_id from /metrics
  /// The server's CPU and RSS come from its /metrics; /proc is read besides (for the comparison
  /// in the report) only as this allows.
  ServerProc server_proc = ServerProc::Auto;
  std::string out = "loadtest-out";  ///< directory written (created)
  bool plots = true;                 ///< run gnuplot for the PNGs
  bool progress = true;              ///< one line per scrape on stderr

  /// Empty when usable; otherwise the first wrong field, its allowed range and its value.
  std::string validate() const;
  /// The bot counts run: `sweep`, or `bots` alone.
  std::vector<int> steps() const;
};

/// "60", "60s", "1.5m", "250ms" → seconds; nullopt when malformed or negative.
std::optional<double> parse_duration_s(const std::string& text);
/// "100,200,400" → {100, 200, 400}; nullopt when malformed, empty or not increasing.
std::optional<std::vector<int>> parse_bot_counts(const std::string& text);
/// "HOST[:CONTROL_PORT[:ADMIN_PORT]],..." → the servers (numeric IPv4 hosts; a port left out is
/// the default given), or why not ("server 2 (\"x:1\"): ...").
std::variant<std::vector<ServerEndpoint>, std::string> parse_servers(
    const std::string& text, std::uint16_t default_control_port, std::uint16_t default_admin_port);
/// "a,b,,c" → {"a", "b", "", "c"}; "" → {} (the per-server lists of --fingerprint and
/// --admin-token-file).
std::vector<std::string> split_list(const std::string& text);
/// True for a numeric IPv4 address in 127.0.0.0/8.
bool is_loopback_v4(const std::string& address);
/// `count` loopback source addresses 127.0.1.1, 127.0.1.2, ... (254 per third octet).
std::vector<std::string> source_addresses(int count);

}  // namespace ricochet::loadtest
