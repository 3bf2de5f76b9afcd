#include "ricochet/loadtest/soak_run.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "ricochet/bot/bot_metrics.h"
#include "ricochet/bot/control_client.h"
#include "ricochet/loadtest/proc_stats.h"
#include "ricochet/loadtest/server_figures.h"

namespace ricochet::loadtest {

namespace asio = boost::asio;

namespace {

constexpr int kTickPhases = 8;  ///< as load_run.cpp: 8 timer wake-ups per tick for every bot
/// Failed attempts in a row before a bot gives up (its slot then waits for its next bot).
constexpr int kMaxReconnectAttempts = 20;
constexpr double kMiB = 1024.0 * 1024.0;

std::chrono::microseconds micros(double seconds) {
  return std::chrono::microseconds(static_cast<std::int64_t>(seconds * 1e6));
}

bot::ServerTrust make_trust(const ServerEndpoint& server) {
  if (!server.fingerprint.empty()) {
    return bot::ServerTrust::pinned(bot::normalize_fingerprint(server.fingerprint).value_or(""));
  }
  return bot::ServerTrust::on_first_use(server.trust_file);
}

/// The bots' own counters of what they refused, added into `out`.
void add_counters(const bot::BotMetrics& metrics, ErrorCounts& out) {
  out["send_failures"] += metrics.send_failures;
  out["snapshots_refused"] += metrics.snapshots_refused;
  out["bad_payloads"] += metrics.bad_payloads;
  out["bad_events"] += metrics.bad_events;
  out["bad_control"] += metrics.bad_control;
}

}  // namespace

SoakRun::SoakRun(asio::io_context& io, LoadTestConfig run, SoakConfig soak)
    : io_(io),
      config_(std::move(run)),
      soak_(std::move(soak)),
      plan_(soak_.churn, config_.name, config_.bots, 1),
      addresses_(source_addresses((config_.bots + config_.bots_per_address - 1) /
                                  config_.bots_per_address)),
      admin_(asio::ip::make_address(config_.servers.front().host),
             config_.servers.front().admin_port),
      tls_(bot::make_control_tls_context()),
      trust_(make_trust(config_.servers.front())),
      slots_(static_cast<std::size_t>(config_.bots)),
      end_timer_(io),
      starter_(io),
      scraper_(io, admin_, config_.servers.front().admin_token, config_.scrape_interval_s,
               [this](const std::string& kind) { count(kind); }),
      server_pid_(config_.server_pid) {}

SoakRun::~SoakRun() = default;

double SoakRun::now_s() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_at_).count();
}

void SoakRun::start() {
  started_at_ = std::chrono::steady_clock::now();
  if (config_.shared_game_port) {
    std::string error;
    shared_port_ = bot::SharedGamePort::open(io_, error);
    if (!shared_port_) {
      count("shared_game_port");
      std::fprintf(stderr, "ricochet-loadtest: %s\n", error.c_str());
      return stop(error);
    }
  }
  std::fprintf(stderr,
               "ricochet-loadtest: soak: %d bots (started %.1f per s), %.0f s; link each way "
               "%.0f ± %.0f ms, loss %.0f %%, duplicated %.0f %%, reordered %.0f %%; lives %s\n",
               config_.bots, config_.ramp_per_s, config_.duration_s, soak_.link.latency_ms,
               soak_.link.jitter_ms, soak_.link.loss * 100, soak_.link.duplicate * 100,
               soak_.link.reorder * 100,
               soak_.churn.active()
                   ? (std::to_string(static_cast<int>(soak_.churn.min_life_s)) + ".." +
                      std::to_string(static_cast<int>(soak_.churn.max_life_s)) + " s")
                         .c_str()
                   : "the whole run");
  end_timer_.expires_after(micros(config_.duration_s));
  end_timer_.async_wait([this](const boost::system::error_code& error) {
    if (!error) stop("duration reached");
  });
  scraper_.start(
      started_at_, [this] { churn(); },
      [this](MetricsScraper::Scrape scrape) { on_scrape(std::move(scrape)); });
  start_next_slot();
}

void SoakRun::start_next_slot() {
  if (finished_ || slots_started_ >= slots_.size()) return;
  begin_incarnation(slots_started_++);
  if (slots_started_ >= slots_.size()) return;
  starter_.expires_after(micros(1.0 / config_.ramp_per_s));
  starter_.async_wait([this](const boost::system::error_code& error) {
    if (!error) start_next_slot();
  });
}

void SoakRun::begin_incarnation(std::size_t index) {
  Slot& slot = slots_[index];
  const Incarnation next = plan_.next(static_cast<int>(index) + 1);
  bot::BotConfig config;
  config.host = config_.servers.front().host;
  config.control_port = config_.servers.front().control_port;
  config.bind_address = addresses_[index % addresses_.size()];
  config.tick_phases = kTickPhases;
  config.fingerprint = config_.servers.front().fingerprint;
  config.trust_file = config_.servers.front().trust_file;
  config.name = next.account;
  config.password = config_.password;
  config.skill = config_.skill;
  config.seed = ++bots_made_;
  config.link = soak_.link;
  config.max_reconnect_attempts = kMaxReconnectAttempts;
  config.predict = !config_.cheap;
  slot.bot = std::make_unique<bot::Bot>(io_, tls_, trust_, std::move(config));
  slot.bot->on_failure([this](std::string_view reason) { count(error_kind(reason)); });
  if (shared_port_) slot.bot->share_game_port(shared_port_);
  slot.leaves_at_s = next.life_s > 0 ? now_s() + next.life_s : 0;
  if (next.new_account) ++new_accounts_;
  slot.bot->start();
}

void SoakRun::churn() {
  const double now = now_s();
  for (std::size_t i = 0; i < slots_started_; ++i) {
    Slot& slot = slots_[i];
    if (slot.leaves_at_s == 0 || now < slot.leaves_at_s) continue;
    retire(slot);
    ++departures_;
    begin_incarnation(i);
  }
}

void SoakRun::retire(Slot& slot) {
  if (!slot.bot) return;
  slot.bot->stop("lifetime over");
  note_results(*slot.bot);
  const bot::BotMetrics metrics = slot.bot->metrics();
  retired_.snapshots += metrics.snapshots;
  retired_.snapshots_lost += metrics.snapshots_lost;
  retired_.server_packets += metrics.server_packets;
  retired_.server_packets_missing += metrics.server_packets_missing;
  add_counters(metrics, retired_.counters);
  if (slot.bot->record().account_id != 0) ++sign_ins_;
  slot.bot.reset();
}

void SoakRun::note_results(const bot::Bot& bot) {
  for (const auto& results : bot.record().results) matches_finished_.insert(results.match_id());
}

void SoakRun::stop(std::string_view reason) {
  if (finished_) return;
  stop_reason_ = std::string(reason);
  finish();
}

void SoakRun::finish() {
  finished_ = true;
  finished_at_s_ = now_s();
  end_timer_.cancel();
  starter_.cancel();
  scraper_.stop();
  for (Slot& slot : slots_) {
    if (slot.bot) slot.bot->stop(stop_reason_);
  }
  std::fprintf(stderr, "ricochet-loadtest: soak finished (%s)\n", stop_reason_.c_str());
  if (auto callback = std::move(on_finished_)) callback();
}

ErrorCounts SoakRun::refusals() const {
  ErrorCounts counters = retired_.counters;
  for (const Slot& slot : slots_) {
    if (slot.bot) add_counters(slot.bot->metrics(), counters);
  }
  return counters;
}

void SoakRun::on_scrape(MetricsScraper::Scrape scrape) {
  SoakSample sample;
  sample.t_s = now_s();
  if (scrape.figures) {
    const ServerFigures& figures = *scrape.figures;
    sample.server_ok = true;
    sample.server_matches = figures.matches;
    sample.server_players = figures.players;
    const TickQuantiles tick = figures.worst_tick();
    sample.tick_p99_ms = tick.p99_ms;
    sample.tick_max_ms = tick.max_ms;
    sample.open_fds = figures.open_fds;
    if (figures.db_bytes >= 0) sample.db_mib = figures.db_bytes / kMiB;
    if (server_pid_ == 0) server_pid_ = figures.pid;
  }

  std::string error;
  double wall = 0;
  if (!samples_.empty()) wall = sample.t_s - samples_.back().t_s;
  if (server_pid_ > 0) {
    if (const auto proc = read_proc(server_pid_, error)) {
      sample.rss_mib = proc->rss_bytes / kMiB;
      if (last_server_cpu_s_ >= 0 && wall > 0) {
        sample.server_cpu_percent = (proc->cpu_s - last_server_cpu_s_) / wall * 100;
      }
      last_server_cpu_s_ = proc->cpu_s;
    } else {
      count("server_proc_unreadable");
    }
  }
  if (const auto self = read_proc(static_cast<int>(getpid()), error)) {
    if (wall > 0) sample.generator_cpu_percent = (self->cpu_s - last_generator_cpu_s_) / wall * 100;
    last_generator_cpu_s_ = self->cpu_s;
  }

  double snapshots = static_cast<double>(retired_.snapshots);
  double lost = static_cast<double>(retired_.snapshots_lost);
  double packets = static_cast<double>(retired_.server_packets);
  double missing_packets = static_cast<double>(retired_.server_packets_missing);
  sample.sign_ins = sign_ins_;
  for (const Slot& slot : slots_) {
    if (!slot.bot) continue;
    switch (slot.bot->state()) {
      case bot::BotState::Playing:
        ++sample.playing;
        break;
      case bot::BotState::Done:
        ++sample.gave_up;
        break;
      default:
        ++sample.joining;
        break;
    }
    const bot::BotMetrics metrics = slot.bot->metrics();
    snapshots += static_cast<double>(metrics.snapshots);
    lost += static_cast<double>(metrics.snapshots_lost);
    packets += static_cast<double>(metrics.server_packets);
    missing_packets += static_cast<double>(metrics.server_packets_missing);
    if (slot.bot->record().account_id != 0) ++sample.sign_ins;
    note_results(*slot.bot);
  }
  const double received = snapshots - last_snapshots_;
  const double missed = lost - last_lost_;
  sample.snapshot_loss = received + missed > 0 ? missed / (received + missed) : 0;
  sample.snapshots = snapshots;
  sample.snapshots_lost = lost;
  sample.server_packets = packets;
  sample.server_packets_missing = missing_packets;
  last_snapshots_ = snapshots;
  last_lost_ = lost;
  sample.new_accounts = new_accounts_;
  sample.departures = departures_;
  sample.matches_finished = matches_finished_.size();
  for (const auto& [kind, n] : errors_) sample.errors += n;
  samples_.push_back(sample);
  if (config_.progress) print_progress(sample);
}

void SoakRun::print_progress(const SoakSample& s) const {
  std::fprintf(stderr,
               "[%7.1fs soak] bots %d playing, %d joining, %d gave up | sign-ins %llu, left %llu "
               "| matches %d, finished %llu | tick ms p99 %.2f max %.2f | rss %.1f MiB fds %.0f "
               "db %.2f MiB | cpu server %.0f%% gen %.0f%% | loss %.1f%% | errors %llu\n",
               s.t_s, s.playing, s.joining, s.gave_up, static_cast<unsigned long long>(s.sign_ins),
               static_cast<unsigned long long>(s.departures), s.server_matches,
               static_cast<unsigned long long>(s.matches_finished), s.tick_p99_ms, s.tick_max_ms,
               s.rss_mib, s.open_fds, s.db_mib, s.server_cpu_percent, s.generator_cpu_percent,
               s.snapshot_loss * 100, static_cast<unsigned long long>(s.errors));
}

}  // namespace ricochet::loadtest
