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

namespace ricochet::bot {

struct FleetConfig {
  BotConfig bot;  ///< every bot's, with the name and seed made per bot
  int bots = 1;   ///< 1..10000; with 1 the name is used as is
  std::chrono::milliseconds start_spacing{20};  ///< between two bots' starts
  /// Local addresses the bots bind to, bot k to [(k - 1) % size]; empty: bot.bind_address.
  std::vector<std::string> bind_addresses;

  std::string validate() const;
};

class Fleet {
 public:
  /// config must be valid. The trust is pinned when config.bot.fingerprint is set, otherwise
  /// on first use into config.bot.trust_file.
  Fleet(boost::asio::io_context& io, FleetConfig config);

  void start();
  void stop(std::string_view reason);
  bool done() const { return done_count_ == bots_.size(); }
  /// Called once when every bot is Done.
  void on_done(std::function<void()> callback) { on_done_ = std::move(callback); }

  const std::vector<std::unique_ptr<Bot>>& bots() const { return bots_; }
  /// One JSON object (no newline): the bots' metrics summed, and each bot's.
  std::string report_json() const;

 private:
  boost::asio::io_context& io_;
  FleetConfig config_;
  boost::asio::ssl::context tls_;
  ServerTrust trust_;
  std::vector<std::unique_ptr<Bot>> bots_;
  boost::asio::steady_timer starter_;
  std::size_t started_ = 0;
  std::size_t done_count_ = 0;
  std::function<void()> on_done_;
};

}  // namespace ricochet::bot
