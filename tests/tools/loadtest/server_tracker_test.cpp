#include "ricochet/loadtest/server_tracker.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <variant>

#include "ricochet/loadtest/error_kinds.h"
#include "ricochet/loadtest/prometheus_text.h"

namespace ricochet::loadtest::server_tracker_test {
namespace {

/// The figures of a /metrics text that must parse.
ServerFigures figures_of(const std::string& text) {
  auto parsed = parse_prometheus_text(text);
  EXPECT_TRUE(std::holds_alternative<std::vector<MetricSample>>(parsed));
  return read_server_figures(std::get<std::vector<MetricSample>>(parsed));
}

ServerFigures with_cpu(double cpu_s, double rss_bytes = 50e6) {
  return figures_of("ricochet_process_id 4242\nprocess_cpu_seconds_total " + std::to_string(cpu_s) +
                    "\nprocess_resident_memory_bytes " + std::to_string(rss_bytes) + "\n");
}

struct Counted {
  ErrorCounts kinds;
  ServerTracker::Count count() {
    return [this](const std::string& kind) { ++kinds[kind]; };
  }
};

TEST(ServerTracker, CpuAndRssComeFromTheServersOwnMetrics) {
  Counted counted;
  ServerTracker tracker("10.0.0.5:7777", ServerProc::Auto, /*loopback=*/false, 0, counted.count());
  EXPECT_EQ(tracker.proc_pid(), 0);  // not on this host: /proc is never asked for
  tracker.observe(10.0, with_cpu(100.0), std::nullopt);
  EXPECT_EQ(tracker.latest().cpu_percent, -1);  // a rate needs two scrapes
  tracker.observe(12.0, with_cpu(101.5, 60e6), std::nullopt);
  EXPECT_DOUBLE_EQ(tracker.latest().cpu_percent, 75.0);  // 1.5 s of CPU in 2 s
  EXPECT_DOUBLE_EQ(tracker.latest().rss_mb, 60.0);
  EXPECT_EQ(tracker.proc_pid(), 0);  // ricochet_process_id is no reason to read a remote /proc
  tracker.observe(14.0, with_cpu(102.5), std::nullopt);
  const ServerWindow window = tracker.window(11.0, 14.0);
  EXPECT_TRUE(window.scraped);
  EXPECT_DOUBLE_EQ(window.cpu_percent, 62.5);  // 2.5 s of CPU in 4 s, from the scrape before
  EXPECT_DOUBLE_EQ(window.rss_mb, 60.0);
  EXPECT_EQ(window.cpu_percent_proc, -1);
  EXPECT_TRUE(counted.kinds.empty());
}

ServerFigures with_tickets(double assigned, double refused) {
  return figures_of("ricochet_placement_tickets_total{result=\"assigned\"} " +
                    std::to_string(assigned) +
                    "\nricochet_placement_tickets_total{result=\"no_server_available\"} " +
                    std::to_string(refused) + "\n");
}

TEST(ServerTracker, PlacementTicketsAreCountedOverTheStepFromItsBaseline) {
  Counted counted;
  ServerTracker tracker("a:1", ServerProc::Off, true, 0, counted.count());
  tracker.observe(0.0, with_tickets(100, 7), std::nullopt);  // before the step: the baseline
  tracker.observe(1.0, std::nullopt, std::nullopt);          // a failed scrape is skipped
  tracker.observe(2.0, with_tickets(112, 7), std::nullopt);
  tracker.observe(3.0, with_tickets(116, 9), std::nullopt);
  tracker.observe(4.0, with_tickets(130, 9), std::nullopt);  // after the step
  EXPECT_EQ(tracker.placement_tickets(0.5, 3.5),
            (std::map<std::string, double>{{"assigned", 16}, {"no_server_available", 2}}));
  // A step that began before the first scrape counts from the first.
  EXPECT_EQ(tracker.placement_tickets(-1.0, 2.0),
            (std::map<std::string, double>{{"assigned", 12}, {"no_server_available", 0}}));
  // A restart (a counter that went back) leaves that result out.
  tracker.observe(5.0, with_tickets(3, 10), std::nullopt);
  EXPECT_EQ(tracker.placement_tickets(3.5, 5.0),
            (std::map<std::string, double>{{"no_server_available", 1}}));
  EXPECT_TRUE(tracker.placement_tickets(-2.0, -1.0).empty());  // no scrape yet
}

TEST(ServerTracker, MissingBadAndResetCountersAreCountedAndLeftOut) {
  Counted counted;
  ServerTracker tracker("a:1", ServerProc::Off, true, 0, counted.count());
  tracker.observe(0.0, with_cpu(10.0), std::nullopt);
  tracker.observe(1.0, figures_of("ricochet_matches 1\n"), std::nullopt);  // no CPU counter
  EXPECT_EQ(tracker.latest().cpu_percent, -1);
  tracker.observe(2.0, with_cpu(11.0), std::nullopt);
  EXPECT_EQ(tracker.latest().cpu_percent, -1);  // its previous scrape had none
  tracker.observe(3.0,
                  figures_of("process_cpu_seconds_total NaN\n"
                             "process_resident_memory_bytes -5\n"),
                  std::nullopt);
  tracker.observe(4.0, with_cpu(11.5), std::nullopt);
  tracker.observe(5.0, with_cpu(0.25), std::nullopt);  // the server restarted
  EXPECT_EQ(tracker.latest().cpu_percent, -1);
  tracker.observe(6.0, std::nullopt, std::nullopt);  // a failed scrape (counted by the scraper)
  tracker.observe(7.0, with_cpu(0.75), std::nullopt);
  tracker.observe(8.0, with_cpu(1.25), std::nullopt);
  EXPECT_DOUBLE_EQ(tracker.latest().cpu_percent, 50.0);
  EXPECT_EQ(counted.kinds["server_cpu_missing"], 2u);
  EXPECT_EQ(counted.kinds["metrics_bad_value"], 2u);
  EXPECT_EQ(counted.kinds["server_cpu_reset"], 1u);
  // Only the intervals with the counter at both ends and not going back: 7→8 (0.5 s in 1 s).
  EXPECT_DOUBLE_EQ(tracker.window(0.5, 8.0).cpu_percent, 50.0);
  EXPECT_EQ(tracker.window(0.5, 5.5).cpu_percent, -1);
  EXPECT_EQ(tracker.window(8.5, 9.0).scraped, false);
}

TEST(ServerTracker, ProcIsReadOnLoopbackInAutoAndGivenUpWhenUnreadable) {
  Counted counted;
  ServerTracker off("a:1", ServerProc::Off, true, 4242, counted.count());
  EXPECT_EQ(off.proc_pid(), 0);
  ServerTracker auto_mode("a:1", ServerProc::Auto, true, 0, counted.count());
  EXPECT_EQ(auto_mode.proc_pid(), 0);  // the pid comes with the first scrape
  auto_mode.observe(0.0, with_cpu(1.0), std::nullopt);
  EXPECT_TRUE(counted.kinds.empty());  // not asked for yet, so not a miss
  EXPECT_EQ(auto_mode.proc_pid(), 4242);
  auto_mode.observe(1.0, with_cpu(1.5), ProcSample{2.0, 50e6});
  auto_mode.observe(2.0, with_cpu(2.0), ProcSample{2.52, 51e6});
  EXPECT_DOUBLE_EQ(auto_mode.latest().cpu_percent, 50.0);
  EXPECT_NEAR(auto_mode.latest().cpu_percent_proc, 52.0, 1e-9);
  const ServerWindow window = auto_mode.window(1.5, 2.0);
  EXPECT_NEAR(window.cpu_percent_proc, 52.0, 1e-9);
  EXPECT_DOUBLE_EQ(window.rss_mb_proc, 51.0);
  auto_mode.observe(3.0, with_cpu(2.5), std::nullopt);  // asked for, did not read
  EXPECT_EQ(counted.kinds["server_proc_unreadable"], 1u);
  EXPECT_EQ(auto_mode.proc_pid(), 0);  // given up: /metrics only from now on
  auto_mode.observe(4.0, with_cpu(3.0), std::nullopt);
  EXPECT_EQ(counted.kinds["server_proc_unreadable"], 1u);
  EXPECT_DOUBLE_EQ(auto_mode.latest().cpu_percent, 50.0);
}

TEST(ServerTracker, ServerProcModesHaveNames) {
  EXPECT_EQ(parse_server_proc("off"), ServerProc::Off);
  EXPECT_EQ(parse_server_proc("auto"), ServerProc::Auto);
  EXPECT_FALSE(parse_server_proc("on"));
  EXPECT_STREQ(name(ServerProc::Off), "off");
  EXPECT_STREQ(name(ServerProc::Auto), "auto");
}

}  // namespace
}  // namespace ricochet::loadtest::server_tracker_test
