#include "ricochet/loadtest/load_run.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "ricochet/bot/bot_metrics.h"
#include "ricochet/loadtest/capacity.h"
#include "ricochet/loadtest/fleet_plan.h"
#include "ricochet/loadtest/server_figures.h"
#include "ricochet/stats/percentile.h"

namespace ricochet::loadtest {

namespace asio = boost::asio;

namespace {

/// The bots' input ticks fall on 8 phases of a shared grid: 8 timer wake-ups per tick for the
/// whole process (not one per bot), and bursts at the server of an eighth of the bots.
constexpr int kTickPhases = 8;

std::chrono::microseconds micros(double seconds) {
  return std::chrono::microseconds(static_cast<std::int64_t>(seconds * 1e6));
}

double safe_ratio(double numerator, double denominator) {
  return denominator > 0 ? numerator / denominator : 0.0;
}

/// "meets the capacity criteria", or the criteria missed ("misses tick_p99, overruns").
std::string shortfall_text(const std::vector<CapacityShortfall>& missed) {
  if (missed.empty()) return "meets the capacity criteria";
  std::string text = "misses";
  for (std::size_t i = 0; i < missed.size(); ++i)
    text += (i == 0 ? " " : ", ") + std::string(name(missed[i]));
  return text;
}

}  // namespace

const char* name(RunPhase phase) {
  switch (phase) {
    case RunPhase::Ramping:
      return "ramping";
    case RunPhase::Measuring:
      return "measuring";
    case RunPhase::Finished:
      return "finished";
  }
  return "unknown";
}

LoadRun::LoadRun(asio::io_context& io, LoadTestConfig config)
    : io_(io),
      config_(std::move(config)),
      targets_(config_.steps()),
      addresses_(source_addresses((targets_.back() + config_.bots_per_address - 1) /
                                  config_.bots_per_address)),
      phase_timer_(io) {
  const auto count_kind = [this](const std::string& kind) { count(kind); };
  for (const ServerEndpoint& server : config_.servers) {
    trackers_.emplace_back(server.label(), config_.server_proc, is_loopback_v4(server.host),
                           config_.servers.size() == 1 ? config_.server_pid : 0, count_kind);
    scrapers_.push_back(std::make_unique<MetricsScraper>(
        io, asio::ip::tcp::endpoint(asio::ip::make_address(server.host), server.admin_port),
        server.admin_token, config_.scrape_interval_s, count_kind));
  }
}

LoadRun::~LoadRun() = default;

double LoadRun::now_s() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_at_).count();
}

void LoadRun::start() {
  started_at_ = std::chrono::steady_clock::now();
  // The first scrape of every server is due now, and the first step begins once each has
  // answered (or failed): the baseline of the counters a step counts from its start
  // (placement tickets), taken before any bot could move them.
  const auto first_due = started_at_ - micros(config_.scrape_interval_s);
  for (std::size_t i = 0; i < scrapers_.size(); ++i) {
    scrapers_[i]->start(first_due, nullptr, [this, i](MetricsScraper::Scrape scrape) {
      on_scrape(i, std::move(scrape));
    });
  }
}

void LoadRun::begin_step() {
  const int target = targets_[steps_.size()];
  const int added = target - bots_started_;
  Step step;
  step.target = target;
  step.started_t_s = now_s();
  // Placed bots all ask the first server, which sends each where it has a seat.
  const std::vector<FleetPlan> plans =
      plan_fleets(bots_started_, added, config_.find_match.empty() ? config_.servers.size() : 1);
  // The fleets start together, each at the ramp rate over the servers' count, so the step's
  // bots start at the ramp rate in all.
  const auto spacing = std::chrono::milliseconds(static_cast<std::int64_t>(
      std::lround(1000.0 * static_cast<double>(plans.size()) / config_.ramp_per_s)));
  for (const FleetPlan& plan : plans) {
    const ServerEndpoint& server = config_.servers[plan.server];
    const bool loopback = is_loopback_v4(server.host);
    bot::FleetConfig fleet;
    fleet.bot.host = server.host;
    fleet.bot.control_port = server.control_port;
    fleet.bot.fingerprint = server.fingerprint;
    fleet.bot.trust_file = server.trust_file;
    // <name>s<step>-<k>; with several servers <name>s<step>.<server>-<k>, so that no two bots
    // share an account when the servers share a database.
    fleet.bot.name = config_.name + "s" + std::to_string(steps_.size() + 1);
    if (config_.servers.size() > 1) fleet.bot.name += "." + std::to_string(plan.server + 1);
    fleet.bot.password = config_.password;
    fleet.bot.skill = config_.skill;
    fleet.bot.seed = static_cast<std::uint64_t>(plan.bots.front()) + 1;
    fleet.bot.find_match = config_.find_match;
    fleet.bot.predict = !config_.cheap;
    fleet.bot.max_reconnect_attempts = 20;
    fleet.bot.tick_phases = kTickPhases;
    // The shared game socket and the loopback source addresses need a server on loopback; a
    // server elsewhere gets each bot on sockets of its own from the default address.
    fleet.shared_game_port = config_.shared_game_port && loopback;
    fleet.bots = static_cast<int>(plan.bots.size());
    fleet.start_spacing = spacing;
    // Bot k of the run binds to address k % addresses (consecutive starts come from different
    // addresses, so no address meets the server's per-address rates during the ramp).
    if (loopback) {
      for (const int k : plan.bots) {
        fleet.bind_addresses.push_back(addresses_[static_cast<std::size_t>(k) % addresses_.size()]);
      }
    }
    auto made = std::make_unique<bot::Fleet>(io_, std::move(fleet));
    for (const auto& each : made->bots()) {
      each->on_failure([this](std::string_view reason) { count(error_kind(reason)); });
    }
    step.fleets.push_back(std::move(made));
  }
  for (const auto& fleet : step.fleets) {
    if (std::string error = fleet->start(); !error.empty()) {
      count("shared_game_port");
      std::fprintf(stderr, "ricochet-loadtest: %s\n", error.c_str());
      steps_.push_back(std::move(step));
      return stop(error);
    }
  }
  bots_started_ = target;
  steps_.push_back(std::move(step));
  phase_ = RunPhase::Ramping;
  const double ramp_s = static_cast<double>(added) / config_.ramp_per_s + config_.settle_s;
  std::fprintf(stderr,
               "ricochet-loadtest: step %zu: %d bots (+%d over %.1f s, then %.0f s "
               "settling), then %.0f s measured\n",
               steps_.size(), target, added, ramp_s - config_.settle_s, config_.settle_s,
               config_.duration_s);
  phase_timer_.expires_after(micros(ramp_s));
  phase_timer_.async_wait([this](const boost::system::error_code& error) {
    if (!error) begin_measuring();
  });
}

void LoadRun::begin_measuring() {
  phase_ = RunPhase::Measuring;
  steps_.back().first_window_sample = samples_.size();
  steps_.back().window_t_s = now_s();
  phase_timer_.expires_after(micros(config_.duration_s));
  phase_timer_.async_wait([this](const boost::system::error_code& error) {
    if (!error) end_step();
  });
}

void LoadRun::end_step() {
  summaries_.push_back(summarise(steps_.back()));
  const StepSummary& done = summaries_.back();
  std::fprintf(stderr,
               "ricochet-loadtest: step %zu done: %d of %d bots connected, tick p99 %.2f ms, "
               "overruns %.0f, loss %.2f %%, server cpu %.0f %%, generator cpu %.0f %% (%s)\n",
               steps_.size(), done.bots_connected, done.bots, done.server_tick.p99_ms,
               done.overruns, done.snapshot_loss * 100, done.server_cpu_percent,
               done.generator_cpu_percent, shortfall_text(capacity_shortfalls(done)).c_str());
  if (steps_.size() < targets_.size()) return begin_step();
  stop_reason_ = "every step measured";
  finish();
}

void LoadRun::stop(std::string_view reason) {
  if (phase_ == RunPhase::Finished) return;
  stop_reason_ = std::string(reason);
  if (phase_ == RunPhase::Measuring && !steps_.empty() && summaries_.size() < steps_.size()) {
    summaries_.push_back(summarise(steps_.back()));
  }
  finish();
}

void LoadRun::finish() {
  phase_ = RunPhase::Finished;
  phase_timer_.cancel();
  for (auto& scraper : scrapers_) scraper->stop();
  for (Step& step : steps_) {
    for (const auto& fleet : step.fleets) fleet->stop(stop_reason_);
  }
  std::fprintf(stderr, "ricochet-loadtest: finished (%s)\n", stop_reason_.c_str());
  if (auto callback = std::move(on_finished_)) callback();
}

void LoadRun::on_scrape(std::size_t server, MetricsScraper::Scrape scrape) {
  ServerTracker& tracker = trackers_[server];
  std::optional<ProcSample> proc;
  if (const int pid = tracker.proc_pid(); pid > 0) {
    std::string error;
    proc = read_proc(pid, error);
  }
  const ServerPoint& point = tracker.observe(now_s(), scrape.figures, proc);
  if (scrape.figures) {
    for (const auto& [id, match] : scrape.figures->by_match) {
      if (match.connected > 0) {
        match_rows_.push_back({point.t_s, static_cast<std::uint32_t>(server), id, match.tick});
      }
    }
  }
  // The first server's scrapes are the run's clock: a sample of the bots and of every server's
  // latest scrape.
  if (server == 0) take_sample(scrape.elapsed_ms);
  const bool baseline_taken =
      std::all_of(trackers_.begin(), trackers_.end(),
                  [](const ServerTracker& t) { return !t.points().empty(); });
  if (steps_.empty() && phase_ != RunPhase::Finished && baseline_taken) begin_step();
}

void LoadRun::take_sample(double scrape_ms) {
  RunSample sample;
  Totals totals;
  sample.t_s = totals.t_s = now_s();
  sample.step_bots = steps_.empty() ? 0 : steps_.back().target;
  sample.measuring = phase_ == RunPhase::Measuring;
  sample.scrape_ms = scrape_ms;
  const Totals* previous = totals_.empty() ? nullptr : &totals_.back();

  // The servers' latest figures.
  sample.server_ok = true;
  double p99_mean_sum = 0;
  int with_players = 0;
  for (const ServerTracker& tracker : trackers_) {
    const ServerPoint& point = tracker.latest();
    sample.server_ok = sample.server_ok && point.ok;
    if (!point.ok) continue;
    sample.matches += point.matches;
    sample.server_players += point.players;
    sample.tick = sample.tick.worst_with(point.tick);
    if (point.tick_p99_mean_ms > 0) {
      p99_mean_sum += point.tick_p99_mean_ms;
      ++with_players;
    }
    sample.server_cpu_percent = std::max(sample.server_cpu_percent, point.cpu_percent);
    sample.server_rss_mb = std::max(sample.server_rss_mb, point.rss_mb);
    // Overruns and dropped steps since the run started: from each server's first usable scrape.
    for (const ServerPoint& first : tracker.points()) {
      if (!first.ok) continue;
      sample.overruns += std::max(0.0, point.overruns - first.overruns);
      sample.dropped_steps += std::max(0.0, point.dropped_steps - first.dropped_steps);
      break;
    }
    const std::vector<ServerPoint>& points = tracker.points();
    if (points.size() >= 2) {
      const ServerPoint& before = points[points.size() - 2];
      const double wall = point.t_s - before.t_s;
      if (before.ok && point.packets_in >= before.packets_in) {
        sample.server_packets_in_per_s += safe_ratio(point.packets_in - before.packets_in, wall);
        sample.server_packets_out_per_s += safe_ratio(point.packets_out - before.packets_out, wall);
      }
    }
  }
  sample.tick_p99_mean_ms = safe_ratio(p99_mean_sum, with_players);

  // Our own CPU and RSS from /proc.
  std::string error;
  if (const auto self = read_proc(static_cast<int>(getpid()), error)) {
    totals.generator_cpu_s = self->cpu_s;
    sample.generator_rss_mb = self->rss_bytes / 1e6;
  }

  // The bots.
  std::vector<double> rtts;
  bot_counters_.clear();
  for (const Step& step : steps_) {
    for (const auto& fleet : step.fleets) {
      for (const auto& each : fleet->bots()) {
        switch (each->state()) {
          case bot::BotState::Playing:
            ++sample.playing;
            break;
          case bot::BotState::Done:
            ++sample.done;
            break;
          default:
            ++sample.joining;
            break;
        }
        const bot::BotMetrics metrics = each->metrics();
        totals.bytes_in += static_cast<double>(metrics.bytes_in);
        totals.bytes_out += static_cast<double>(metrics.bytes_out);
        totals.snapshots += static_cast<double>(metrics.snapshots);
        totals.snapshots_lost += static_cast<double>(metrics.snapshots_lost);
        if (each->state() == bot::BotState::Playing && !metrics.rtt_ms.empty()) {
          rtts.push_back(metrics.rtt_ms.back());
        }
        bot_counters_["send_failures"] += metrics.send_failures;
        bot_counters_["snapshots_refused"] += metrics.snapshots_refused;
        bot_counters_["bad_payloads"] += metrics.bad_payloads;
        bot_counters_["bad_events"] += metrics.bad_events;
        bot_counters_["bad_control"] += metrics.bad_control;
      }
    }
  }
  for (const auto& [kind, n] : errors_) sample.errors += n;
  for (const auto& [kind, n] : bot_counters_) sample.errors += n;
  sample.rtt_ms_p50 = stats::percentile(rtts, 50);
  sample.rtt_ms_p99 = stats::percentile(rtts, 99);
  if (sample.measuring && !steps_.empty()) {
    std::vector<double>& pooled = steps_.back().rtt_ms;
    pooled.insert(pooled.end(), rtts.begin(), rtts.end());
  }

  if (previous) {
    const double wall = totals.t_s - previous->t_s;
    const double clients = std::max(1, sample.playing);
    sample.kbps_in_per_client =
        safe_ratio((totals.bytes_in - previous->bytes_in) * 8 / 1000, wall) / clients;
    sample.kbps_out_per_client =
        safe_ratio((totals.bytes_out - previous->bytes_out) * 8 / 1000, wall) / clients;
    const double received = totals.snapshots - previous->snapshots;
    const double lost = totals.snapshots_lost - previous->snapshots_lost;
    sample.snapshot_loss = safe_ratio(lost, received + lost);
    sample.generator_cpu_percent =
        (totals.generator_cpu_s - previous->generator_cpu_s) / wall * 100;
  }
  samples_.push_back(sample);
  totals_.push_back(totals);
  if (config_.progress) print_progress(sample);
}

void LoadRun::print_progress(const RunSample& s) const {
  std::string kinds;
  ErrorCounts all = errors_;
  for (const auto& [kind, n] : bot_counters_) {
    if (n > 0) all[kind] += n;
  }
  for (const auto& [kind, n] : all) {
    if (n == 0) continue;
    if (!kinds.empty()) kinds += ", ";
    kinds += kind + " " + std::to_string(n);
  }
  std::fprintf(stderr,
               "[%6.1fs %-9s] bots %d playing, %d joining, %d gave up of %d | matches %d | tick "
               "ms p99 %.2f max %.2f | overruns %.0f | server cpu %.0f%% rss %.0f MB | gen cpu "
               "%.0f%% | kbps/client in %.0f out %.0f | rtt p99 %.1f ms | loss %.2f%% | errors "
               "%llu%s%s%s\n",
               s.t_s, name(phase_), s.playing, s.joining, s.done, s.step_bots, s.matches,
               s.tick.p99_ms, s.tick.max_ms, s.overruns, s.server_cpu_percent, s.server_rss_mb,
               s.generator_cpu_percent, s.kbps_in_per_client, s.kbps_out_per_client, s.rtt_ms_p99,
               s.snapshot_loss * 100, static_cast<unsigned long long>(s.errors),
               kinds.empty() ? "" : " (", kinds.c_str(), kinds.empty() ? "" : ")");
}

std::vector<double> LoadRun::connect_ms() const {
  std::vector<double> out;
  for (const Step& step : steps_) {
    for (const auto& fleet : step.fleets) {
      for (const auto& each : fleet->bots()) {
        const double ms = each->metrics().first_snapshot_ms;
        if (ms >= 0) out.push_back(ms);
      }
    }
  }
  return out;
}

StepSummary LoadRun::summarise(const Step& step) const {
  StepSummary out;
  out.bots = step.target;
  out.errors = errors_;
  for (const auto& [kind, n] : bot_counters_) {
    if (n > 0) out.errors[kind] += n;
  }
  std::vector<double> connect;
  for (const auto& fleet : step.fleets) {
    for (const auto& each : fleet->bots()) {
      const double ms = each->metrics().first_snapshot_ms;
      if (ms >= 0) connect.push_back(ms);
    }
  }
  out.connect_ms_samples = connect;
  out.rtt_ms_samples = step.rtt_ms;
  out.connect_ms_p50 = stats::percentile(connect, 50);
  out.connect_ms_p99 = stats::percentile(connect, 99);
  out.connect_ms_max = stats::percentile(connect, 100);
  // Placement: where each of the step's bots was placed last, and how long its placements took.
  for (const auto& fleet : step.fleets) {
    for (const auto& each : fleet->bots()) {
      const auto& placements = each->record().placements;
      if (!placements.empty()) ++out.bots_placed[placements.back().server];
      const std::vector<double> ms = each->metrics().placement_ms;
      out.placement_ms_samples.insert(out.placement_ms_samples.end(), ms.begin(), ms.end());
    }
  }
  out.placement_ms_p50 = stats::percentile(out.placement_ms_samples, 50);
  out.placement_ms_p99 = stats::percentile(out.placement_ms_samples, 99);
  out.placement_ms_max = stats::percentile(out.placement_ms_samples, 100);
  out.rtt_ms_p50 = stats::percentile(step.rtt_ms, 50);
  out.rtt_ms_p99 = stats::percentile(step.rtt_ms, 99);
  const std::size_t first = step.first_window_sample;
  if (first >= samples_.size()) return out;  // stopped before a sample of the window
  const std::size_t last = samples_.size() - 1;
  const RunSample& end = samples_[last];
  out.bots_connected = end.playing;
  out.bots_gave_up = end.done;
  out.matches = end.matches;
  out.ramp_s = samples_[first].t_s - step.started_t_s;
  double p99_mean_sum = 0;
  int count = 0;
  for (std::size_t i = first; i <= last; ++i) {
    const RunSample& s = samples_[i];
    out.server_tick = out.server_tick.worst_with(s.tick);
    out.generator_rss_mb = std::max(out.generator_rss_mb, s.generator_rss_mb);
    p99_mean_sum += s.tick_p99_mean_ms;
    ++count;
  }
  out.server_tick_ms_p99_mean = safe_ratio(p99_mean_sum, count);
  // Deltas over the window: from the sample before its first (the window's start) to its last.
  const std::size_t base = first > 0 ? first - 1 : first;
  const Totals& from = totals_[base];
  const Totals& to = totals_[last];
  const double wall = to.t_s - from.t_s;
  out.measured_s = wall;
  const double received = to.snapshots - from.snapshots;
  const double lost = to.snapshots_lost - from.snapshots_lost;
  out.snapshot_loss = safe_ratio(lost, received + lost);
  out.snapshots_received = received;
  out.snapshots_lost = lost;
  const double clients = std::max(1, end.playing);
  out.snapshots_per_s_per_bot = safe_ratio(received, wall) / clients;
  out.kbps_in_per_client = safe_ratio((to.bytes_in - from.bytes_in) * 8 / 1000, wall) / clients;
  out.kbps_out_per_client = safe_ratio((to.bytes_out - from.bytes_out) * 8 / 1000, wall) / clients;
  out.generator_cpu_percent = safe_ratio(to.generator_cpu_s - from.generator_cpu_s, wall) * 100;
  out.kbps_in_total = safe_ratio((to.bytes_in - from.bytes_in) * 8 / 1000, wall);
  out.kbps_out_total = safe_ratio((to.bytes_out - from.bytes_out) * 8 / 1000, wall);
  for (const ServerTracker& tracker : trackers_) {
    out.servers.push_back(tracker.window(step.window_t_s, to.t_s));
    out.servers.back().placement_tickets = tracker.placement_tickets(step.started_t_s, to.t_s);
  }
  out.total_servers();
  return out;
}

}  // namespace ricochet::loadtest
