#pragma once
/// One load test on one io_context: steps of bots (fleets from ricochet_bot, no thread per
/// bot) started at the ramp rate, then measured; a scrape of the server's /metrics at every
/// interval (its CPU and RSS from there; from its /proc besides when ServerProc allows, for the
/// comparison), a progress line per scrape. Refusals are counted by kind, never fatal.
///
///   Ramping ─all started, settled─▶ Measuring ─duration─▶ Ramping (next step) … ─▶ Finished
///   any ─stop()─▶ Finished (the current window is summarised as far as it got)

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "ricochet/bot/fleet.h"
#include "ricochet/loadtest/error_kinds.h"
#include "ricochet/loadtest/loadtest_config.h"
#include "ricochet/loadtest/metrics_scraper.h"
#include "ricochet/loadtest/proc_stats.h"
#include "ricochet/loadtest/run_record.h"
#include "ricochet/loadtest/server_tracker.h"

namespace ricochet::loadtest {

enum class RunPhase : std::uint8_t { Ramping, Measuring, Finished };
const char* name(RunPhase phase);

class LoadRun {
 public:
  /// config must be valid.
  LoadRun(boost::asio::io_context& io, LoadTestConfig config);
  ~LoadRun();
  LoadRun(const LoadRun&) = delete;
  LoadRun& operator=(const LoadRun&) = delete;

  void start();
  /// Ends the run: the current window is summarised, every bot disconnects.
  void stop(std::string_view reason);
  /// Called once when the run is Finished.
  void on_finished(std::function<void()> callback) { on_finished_ = std::move(callback); }

  RunPhase phase() const { return phase_; }
  const std::string& stop_reason() const { return stop_reason_; }
  const std::vector<RunSample>& samples() const { return samples_; }
  const std::vector<MatchTickRow>& match_rows() const { return match_rows_; }
  const std::vector<StepSummary>& steps() const { return summaries_; }
  /// Every bot's start-to-first-snapshot time so far, ms.
  std::vector<double> connect_ms() const;
  const ErrorCounts& errors() const { return errors_; }
  /// Every server's scrapes, in the order of the configuration.
  const std::vector<ServerTracker>& servers() const { return trackers_; }

 private:
  /// Cumulative figures at one sample, for the deltas between two.
  struct Totals {
    double t_s = 0;
    double bytes_in = 0;
    double bytes_out = 0;
    double snapshots = 0;
    double snapshots_lost = 0;
    double generator_cpu_s = 0;
  };
  struct Step {
    int target = 0;
    std::vector<std::unique_ptr<bot::Fleet>> fleets;  ///< one per server given bots
    double started_t_s = 0;
    double window_t_s = 0;                ///< when its measured window began
    std::size_t first_window_sample = 0;  ///< index into samples_
    std::vector<double> rtt_ms;           ///< pooled over the window
  };

  double now_s() const;
  void begin_step();
  void begin_measuring();
  void end_step();
  void finish();
  void on_scrape(std::size_t server, MetricsScraper::Scrape scrape);
  void take_sample(double scrape_ms);
  void count(const std::string& kind, std::uint64_t n = 1) { errors_[kind] += n; }
  void print_progress(const RunSample& sample) const;
  StepSummary summarise(const Step& step) const;

  boost::asio::io_context& io_;
  LoadTestConfig config_;
  std::vector<int> targets_;
  std::vector<std::string> addresses_;
  RunPhase phase_ = RunPhase::Ramping;
  std::string stop_reason_;
  std::function<void()> on_finished_;
  std::chrono::steady_clock::time_point started_at_;
  boost::asio::steady_timer phase_timer_;
  std::vector<ServerTracker> trackers_;
  std::vector<std::unique_ptr<MetricsScraper>> scrapers_;  ///< one per server, as trackers_

  std::vector<Step> steps_;
  int bots_started_ = 0;
  std::vector<RunSample> samples_;
  std::vector<Totals> totals_;  ///< one per sample
  std::vector<MatchTickRow> match_rows_;
  std::vector<StepSummary> summaries_;
  ErrorCounts errors_;        ///< failures reported by bots, plus the scrapes' own
  ErrorCounts bot_counters_;  ///< what the bots' metrics counted (latest totals)
};

}  // namespace ricochet::loadtest
