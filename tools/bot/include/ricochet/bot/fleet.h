#pragma once
/// Many bots on one io_context (no thread per bot): named <name>-<k>, seeded <seed>+k, started
/// a few milliseconds apart so their sign-ins do not arrive in one burst.

#include <boost/asio/io_context.hpp>
#include <boost/asio/ssl/context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "ricochet/bot/bot.h"
#include "ricochet/bot/server_trust.h"
#include "ricochet/bot/shared_game_port.h"

namespace ricochet::bot {

struct FleetConfig {
  BotConfig bot;  ///< every bot's, with the name and seed made per bot
  int bots = 1;   ///< 1..10000; with 1 the name is used as is
  std::chrono::milliseconds start_spacing{20};  ///< between two bots' starts
  /// Local addresses the bots bind to, bot k to [(k - 1) % size]; empty: bot.bind_address.
  std::vector<std::string> bind_addresses;
  /// One UDP socket for every bot's game channel (SharedGamePort: a source address per
  /// connection, batched system calls); the server must be an IPv4 loopback address. False: a
  /// socket per game connection.
  bool shared_game_port = false;

  std::string validate() const;
};

class Fleet {
 public:
  /// config must be valid. The trust is pinned when config.bot.fingerprint is set, otherwise
  /// on first use into config.bot.trust_file.
  Fleet(boost::asio::io_context& io, FleetConfig config);

  /// Opens the shared game port when asked for (empty, else why it cannot be), then starts the
  /// bots one after another.
  [[nodiscard]] std::string start();
  void stop(std::string_view reason);
  bool done() const { return done_count_ == bots_.size(); }
  /// Called once when every bot is Done.
  void on_done(std::function<void()> callback) { on_done_ = std::move(callback); }

  const std::vector<std::unique_ptr<Bot>>& bots() const { return bots_; }
  /// The shared game port (null without one).
  const SharedGamePort* shared_port() const { return shared_port_.get(); }
  /// One JSON object (no newline): the bots' metrics summed, and each bot's.
  std::string report_json() const;

 private:
  void start_next();

  boost::asio::io_context& io_;
  FleetConfig config_;
  boost::asio::ssl::context tls_;
  ServerTrust trust_;
  std::vector<std::unique_ptr<Bot>> bots_;
  std::shared_ptr<SharedGamePort> shared_port_;
  boost::asio::steady_timer starter_;
  std::size_t started_ = 0;
  std::size_t done_count_ = 0;
  std::function<void()> on_done_;
};

}  // namespace ricochet::bot
