#include "ricochet/bot/fleet.h"

#include <cstdio>

#include "ricochet/tools/json_text.h"

namespace ricochet::bot {
namespace {

using tools::json_string;

ServerTrust make_trust(const BotConfig& config) {
  if (!config.fingerprint.empty()) {
    return ServerTrust::pinned(normalize_fingerprint(config.fingerprint).value_or(""));
  }
  return ServerTrust::on_first_use(config.trust_file);
}

}  // namespace

std::string FleetConfig::validate() const {
  if (bots < 1 || bots > 10000) return "bots must be 1..10000, got " + std::to_string(bots);
  if (start_spacing.count() < 0 || start_spacing.count() > 60000) {
    return "start_spacing must be 0..60000 ms, got " + std::to_string(start_spacing.count());
  }
  if (shared_game_port && bot.host.rfind("127.", 0) != 0) {
    return "a shared game port needs an IPv4 loopback server (127.0.0.0/8), got " + bot.host;
  }
  for (const std::string& address : bind_addresses) {
    BotConfig bound = bot;
    bound.bind_address = address;
    if (std::string problem = bound.validate(); !problem.empty()) return problem;
  }
  BotConfig widest = bot;
  if (bots > 1) {
    widest.name += '-';
    widest.name += std::to_string(bots);
  }
  return widest.validate();
}

Fleet::Fleet(boost::asio::io_context& io, FleetConfig config)
    : io_(io),
      config_(std::move(config)),
      tls_(make_control_tls_context()),
      trust_(make_trust(config_.bot)),
      starter_(io) {
  for (int k = 1; k <= config_.bots; ++k) {
    BotConfig bot = config_.bot;
    if (config_.bots > 1) {
      bot.name += '-';
      bot.name += std::to_string(k);
      if (!bot.dump_states.empty()) bot.dump_states += '-' + std::to_string(k);
    }
    bot.seed = config_.bot.seed + static_cast<std::uint64_t>(k) - 1;
    if (!config_.bind_addresses.empty()) {
      bot.bind_address =
          config_.bind_addresses[static_cast<std::size_t>(k - 1) % config_.bind_addresses.size()];
    }
    bots_.push_back(std::make_unique<Bot>(io_, tls_, trust_, std::move(bot)));
    bots_.back()->on_done([this] {
      if (++done_count_ == bots_.size() && on_done_) on_done_();
    });
  }
}

std::string Fleet::start() {
  if (config_.shared_game_port && !shared_port_) {
    std::string error;
    shared_port_ = SharedGamePort::open(io_, error);
    if (!shared_port_) return error;
    for (const auto& bot : bots_) bot->share_game_port(shared_port_);
  }
  start_next();
  return {};
}

void Fleet::start_next() {
  if (started_ >= bots_.size()) return;
  bots_[started_++]->start();
  if (started_ >= bots_.size()) return;
  starter_.expires_after(config_.start_spacing);
  starter_.async_wait([this](const boost::system::error_code& error) {
    if (!error) start_next();
  });
}

void Fleet::stop(std::string_view reason) {
  starter_.cancel();
  started_ = bots_.size();
  for (const auto& bot : bots_) bot->stop(reason);
}

std::string Fleet::report_json() const {
  BotMetrics total;
  std::string per_bot;
  for (const auto& bot : bots_) {
    const BotMetrics metrics = bot->metrics();
    total.merge(metrics);
    if (!per_bot.empty()) per_bot += ',';
    per_bot += "{\"name\":";
    per_bot += json_string(bot->config().name);
    per_bot += ",\"state\":\"";
    per_bot += name(bot->state());
    per_bot += "\",\"error\":";
    per_bot += json_string(bot->record().error);
    per_bot += ",\"metrics\":";
    per_bot += metrics.to_json();
    per_bot += '}';
  }
  std::string out = "{\"bots\":";
  out += std::to_string(bots_.size());
  out += ",\"done\":";
  out += std::to_string(done_count_);
  out += ",\"total\":";
  out += total.to_json();
  out += ",\"per_bot\":[";
  out += per_bot;
  out += "]}";
  return out;
}

}  // namespace ricochet::bot
