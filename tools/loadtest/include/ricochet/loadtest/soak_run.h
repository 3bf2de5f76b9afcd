#pragma once
/// A soak on one io_context: a fixed number of bot slots, every bot's game channel through a bad
/// link (SoakConfig::link), bots leaving after their lifetime and new ones signing in to their
/// slot (ChurnPlan), for the whole duration; the server's /metrics and /proc read at every
/// interval into one SoakSample each. Refusals are counted by kind, never fatal.
///
///   Running ─duration─▶ Finished        Running ─stop()─▶ Finished

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl/context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "ricochet/bot/bot.h"
#include "ricochet/bot/server_trust.h"
#include "ricochet/bot/shared_game_port.h"
#include "ricochet/loadtest/churn_plan.h"
#include "ricochet/loadtest/error_kinds.h"
#include "ricochet/loadtest/loadtest_config.h"
#include "ricochet/loadtest/metrics_scraper.h"
#include "ricochet/loadtest/soak_config.h"
#include "ricochet/loadtest/soak_record.h"

namespace ricochet::loadtest {

class SoakRun {
 public:
  /// Both configs must be valid (SoakConfig::validate with `run`).
  SoakRun(boost::asio::io_context& io, LoadTestConfig run, SoakConfig soak);
  ~SoakRun();
  SoakRun(const SoakRun&) = delete;
  SoakRun& operator=(const SoakRun&) = delete;

  void start();
  /// Ends the run: every bot disconnects.
  void stop(std::string_view reason);
  /// Called once when the run is Finished.
  void on_finished(std::function<void()> callback) { on_finished_ = std::move(callback); }

  bool finished() const { return finished_; }
  const std::string& stop_reason() const { return stop_reason_; }
  double elapsed_s() const { return finished_ ? finished_at_s_ : now_s(); }
  const std::vector<SoakSample>& samples() const { return samples_; }
  /// Failures by kind: the attempts bots reported failed (error_kinds.h) and the scrapes' own.
  const ErrorCounts& errors() const { return errors_; }
  /// What the bots refused or could not send, by counter (snapshots_refused, bad_payloads,
  /// send_failures, ...): on a reordering link most are stale snapshots, refused by design.
  ErrorCounts refusals() const;

 private:
  struct Slot {
    std::unique_ptr<bot::Bot> bot;
    double leaves_at_s = 0;  ///< 0: stays to the end
  };
  /// Counts of the bots that have left, kept when their Bot is destroyed.
  struct Retired {
    std::uint64_t snapshots = 0;
    std::uint64_t snapshots_lost = 0;
    std::uint64_t server_packets = 0;
    std::uint64_t server_packets_missing = 0;
    ErrorCounts counters;
  };

  double now_s() const;
  void start_next_slot();
  /// Puts the slot's next bot in (the previous one, if any, has left).
  void begin_incarnation(std::size_t slot);
  /// Bots past their lifetime leave cleanly and their slot's next bot starts.
  void churn();
  void retire(Slot& slot);
  void note_results(const bot::Bot& bot);
  void finish();
  void on_scrape(MetricsScraper::Scrape scrape);
  void count(const std::string& kind) { errors_[kind] += 1; }
  void print_progress(const SoakSample& sample) const;

  boost::asio::io_context& io_;
  LoadTestConfig config_;
  SoakConfig soak_;
  ChurnPlan plan_;
  std::vector<std::string> addresses_;
  boost::asio::ip::tcp::endpoint admin_;
  boost::asio::ssl::context tls_;
  bot::ServerTrust trust_;
  std::shared_ptr<bot::SharedGamePort> shared_port_;
  std::vector<Slot> slots_;
  std::size_t slots_started_ = 0;
  std::uint64_t bots_made_ = 0;  ///< seeds the bots' behaviour and links

  bool finished_ = false;
  double finished_at_s_ = 0;
  std::string stop_reason_;
  std::function<void()> on_finished_;
  std::chrono::steady_clock::time_point started_at_;
  boost::asio::steady_timer end_timer_;
  boost::asio::steady_timer starter_;
  MetricsScraper scraper_;
  int server_pid_ = 0;

  std::vector<SoakSample> samples_;
  double last_snapshots_ = 0;  ///< at the previous sample, every bot so far
  double last_lost_ = 0;
  double last_server_cpu_s_ = -1;
  double last_generator_cpu_s_ = 0;
  std::uint64_t sign_ins_ = 0;  ///< of retired bots (live ones are added per sample)
  std::uint64_t new_accounts_ = 0;
  std::uint64_t departures_ = 0;
  std::set<std::uint32_t> matches_finished_;
  Retired retired_;
  ErrorCounts errors_;  ///< failures reported by bots, plus the scrapes' own
};

}  // namespace ricochet::loadtest
