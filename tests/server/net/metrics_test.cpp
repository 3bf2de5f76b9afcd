#include "ricochet/server/metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <thread>
#include <vector>

namespace ricochet::server::metrics_test {
namespace {

TEST(Metrics, EmptyRegistryRendersNothing) {
  const MetricsRegistry registry;
  EXPECT_EQ(registry.render(), "");
}

TEST(Metrics, CountersAndGaugesRenderSortedByNameWithHelpAndType) {
  MetricsRegistry registry;
  registry.gauge("ricochet_matches", "Matches open.").set(4);
  Counter& dropped = registry.counter("ricochet_packets_dropped_total", "Datagrams dropped.",
                                      {{"reason", "malformed"}});
  dropped.inc();
  dropped.inc(2);
  registry.counter("ricochet_packets_dropped_total", "Datagrams dropped.", {{"reason", "replayed"}})
      .inc(0.5);
  Gauge& depth = registry.gauge("ricochet_db_queue_depth", "Jobs waiting for the DB worker.");
  depth.add(3);
  depth.add(-1);
  EXPECT_EQ(registry.render(),
            "# HELP ricochet_db_queue_depth Jobs waiting for the DB worker.\n"
            "# TYPE ricochet_db_queue_depth gauge\n"
            "ricochet_db_queue_depth 2\n"
            "# HELP ricochet_matches Matches open.\n"
            "# TYPE ricochet_matches gauge\n"
            "ricochet_matches 4\n"
            "# HELP ricochet_packets_dropped_total Datagrams dropped.\n"
            "# TYPE ricochet_packets_dropped_total counter\n"
            "ricochet_packets_dropped_total{reason=\"malformed\"} 3\n"
            "ricochet_packets_dropped_total{reason=\"replayed\"} 0.5\n");
}

TEST(Metrics, SameNameAndLabelsIsTheSameSeries) {
  MetricsRegistry registry;
  Counter& a = registry.counter("c_total", "C.", {{"x", "1"}});
  Counter& b = registry.counter("c_total", "C.", {{"x", "1"}});
  EXPECT_EQ(&a, &b);
  EXPECT_NE(&a, &registry.counter("c_total", "C.", {{"x", "2"}}));
}

TEST(Metrics, HistogramRendersCumulativeBucketsSumAndCount) {
  MetricsRegistry registry;
  Histogram& tick =
      registry.histogram("ricochet_tick_phase_seconds", "Time per tick phase.",
                         {0.001, 0.005, 0.01}, {{"match", "1"}, {"phase", "physics"}});
  tick.observe(0.0005);
  tick.observe(0.001);  // on a bound: counted in it (le)
  tick.observe(0.007);
  tick.observe(2.0);
  EXPECT_EQ(registry.render(),
            "# HELP ricochet_tick_phase_seconds Time per tick phase.\n"
            "# TYPE ricochet_tick_phase_seconds histogram\n"
            "ricochet_tick_phase_seconds_bucket{match=\"1\",phase=\"physics\",le=\"0.001\"} 2\n"
            "ricochet_tick_phase_seconds_bucket{match=\"1\",phase=\"physics\",le=\"0.005\"} 2\n"
            "ricochet_tick_phase_seconds_bucket{match=\"1\",phase=\"physics\",le=\"0.01\"} 3\n"
            "ricochet_tick_phase_seconds_bucket{match=\"1\",phase=\"physics\",le=\"+Inf\"} 4\n"
            "ricochet_tick_phase_seconds_sum{match=\"1\",phase=\"physics\"} 2.0085\n"
            "ricochet_tick_phase_seconds_count{match=\"1\",phase=\"physics\"} 4\n");
}

TEST(Metrics, HistogramWithoutLabelsAndNanObservation) {
  MetricsRegistry registry;
  Histogram& h = registry.histogram("h", "H.", {1});
  h.observe(std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(registry.render(),
            "# HELP h H.\n"
            "# TYPE h histogram\n"
            "h_bucket{le=\"1\"} 0\n"
            "h_bucket{le=\"+Inf\"} 1\n"
            "h_sum NaN\n"
            "h_count 1\n");
}

TEST(Metrics, LabelValuesAndHelpAreEscaped) {
  MetricsRegistry registry;
  registry.gauge("g", "Help with \\ and\nnewline \"quoted\".", {{"name", "a\"b\\c\nd"}}).set(1);
  EXPECT_EQ(registry.render(),
            "# HELP g Help with \\\\ and\\nnewline \"quoted\".\n"
            "# TYPE g gauge\n"
            "g{name=\"a\\\"b\\\\c\\nd\"} 1\n");
}

TEST(Metrics, SpecialValuesUseTheExpositionSpelling) {
  MetricsRegistry registry;
  registry.gauge("a", "A.", {{"v", "inf"}}).set(std::numeric_limits<double>::infinity());
  registry.gauge("a", "A.", {{"v", "-inf"}}).set(-std::numeric_limits<double>::infinity());
  registry.gauge("a", "A.", {{"v", "big"}}).set(1e21);
  registry.gauge("a", "A.", {{"v", "small"}}).set(-0.25);
  EXPECT_EQ(registry.render(),
            "# HELP a A.\n"
            "# TYPE a gauge\n"
            "a{v=\"inf\"} +Inf\n"
            "a{v=\"-inf\"} -Inf\n"
            "a{v=\"big\"} 1e+21\n"
            "a{v=\"small\"} -0.25\n");
}

TEST(Metrics, CollectCallbacksReportAtScrapeTimeMergedIntoFamilies) {
  MetricsRegistry registry;
  registry.counter("ricochet_connections_total", "Connections accepted.", {{"channel", "control"}})
      .inc(7);
  int players = 3;
  registry.add_collect_callback([&players](MetricsSink& sink) {
    sink.counter("ricochet_connections_total", "Connections accepted.", {{"channel", "game"}}, 5);
    for (int match = 1; match <= 2; ++match) {
      sink.gauge("ricochet_players", "Players seated per match.",
                 {{"match", std::to_string(match)}}, players * match);
    }
    sink.histogram("ricochet_rtt_seconds", "Round-trip times.", {},
                   HistogramSnapshot{{0.05, 0.1}, {1, 2, 3}, 0.9});
  });
  const std::string expected_head =
      "# HELP ricochet_connections_total Connections accepted.\n"
      "# TYPE ricochet_connections_total counter\n"
      "ricochet_connections_total{channel=\"control\"} 7\n"
      "ricochet_connections_total{channel=\"game\"} 5\n"
      "# HELP ricochet_players Players seated per match.\n"
      "# TYPE ricochet_players gauge\n";
  const std::string expected_tail =
      "# HELP ricochet_rtt_seconds Round-trip times.\n"
      "# TYPE ricochet_rtt_seconds histogram\n"
      "ricochet_rtt_seconds_bucket{le=\"0.05\"} 1\n"
      "ricochet_rtt_seconds_bucket{le=\"0.1\"} 3\n"
      "ricochet_rtt_seconds_bucket{le=\"+Inf\"} 6\n"
      "ricochet_rtt_seconds_sum 0.9\n"
      "ricochet_rtt_seconds_count 6\n";
  EXPECT_EQ(registry.render(), expected_head +
                                   "ricochet_players{match=\"1\"} 3\n"
                                   "ricochet_players{match=\"2\"} 6\n" +
                                   expected_tail);
  players = 4;  // read again at the next scrape
  EXPECT_EQ(registry.render(), expected_head +
                                   "ricochet_players{match=\"1\"} 4\n"
                                   "ricochet_players{match=\"2\"} 8\n" +
                                   expected_tail);
}

TEST(Metrics, SummaryRendersQuantilesThenSumAndCount) {
  MetricsRegistry registry;
  registry.add_collect_callback([](MetricsSink& sink) {
    for (const char* match : {"1", "2"}) {
      sink.summary("ricochet_tick_seconds", "Tick time.", {{"match", match}},
                   SummarySnapshot{{{0.5, 0.001}, {0.99, 0.004}, {1, 0.008}}, 1.5, 600});
    }
  });
  EXPECT_EQ(registry.render(),
            "# HELP ricochet_tick_seconds Tick time.\n"
            "# TYPE ricochet_tick_seconds summary\n"
            "ricochet_tick_seconds{match=\"1\",quantile=\"0.5\"} 0.001\n"
            "ricochet_tick_seconds{match=\"1\",quantile=\"0.99\"} 0.004\n"
            "ricochet_tick_seconds{match=\"1\",quantile=\"1\"} 0.008\n"
            "ricochet_tick_seconds_sum{match=\"1\"} 1.5\n"
            "ricochet_tick_seconds_count{match=\"1\"} 600\n"
            "ricochet_tick_seconds{match=\"2\",quantile=\"0.5\"} 0.001\n"
            "ricochet_tick_seconds{match=\"2\",quantile=\"0.99\"} 0.004\n"
            "ricochet_tick_seconds{match=\"2\",quantile=\"1\"} 0.008\n"
            "ricochet_tick_seconds_sum{match=\"2\"} 1.5\n"
            "ricochet_tick_seconds_count{match=\"2\"} 600\n");
}

TEST(Metrics, CollectCallbackMayRegisterMetrics) {
  MetricsRegistry registry;
  registry.add_collect_callback(
      [&registry](MetricsSink&) { registry.gauge("late", "Registered while scraping.").set(1); });
  registry.render();
  EXPECT_NE(registry.render().find("late 1\n"), std::string::npos);
}

TEST(Metrics, ProgrammingErrorsAreRefused) {
  MetricsRegistry registry;
  registry.counter("x_total", "X.");
  EXPECT_THROW(registry.gauge("x_total", "X."), std::invalid_argument);        // other type
  EXPECT_THROW(registry.counter("x_total", "Other."), std::invalid_argument);  // other help
  EXPECT_THROW(registry.counter("1x", "X."), std::invalid_argument);
  EXPECT_THROW(registry.counter("x-y", "X."), std::invalid_argument);
  EXPECT_THROW(registry.counter("y", "Y.", {{"__reserved", "1"}}), std::invalid_argument);
  EXPECT_THROW(registry.counter("y", "Y.", {{"a-b", "1"}}), std::invalid_argument);
  EXPECT_THROW(registry.counter("y", "Y.", {{"a", "1"}, {"a", "2"}}), std::invalid_argument);
  EXPECT_THROW(registry.histogram("h", "H.", {1}, {{"le", "1"}}), std::invalid_argument);
  EXPECT_THROW(registry.histogram("h", "H.", {}), std::invalid_argument);
  EXPECT_THROW(registry.histogram("h", "H.", {2, 1}), std::invalid_argument);
  EXPECT_THROW(registry.histogram("h", "H.", {1, std::nan("")}), std::invalid_argument);
  registry.histogram("h", "H.", {1, 2});
  EXPECT_THROW(registry.histogram("h", "H.", {1, 3}, {{"a", "b"}}), std::invalid_argument);

  MetricsRegistry duplicate;
  duplicate.counter("d_total", "D.", {{"k", "v"}});
  duplicate.add_collect_callback([](MetricsSink& sink) {
    sink.counter("d_total", "D.", {{"k", "v"}}, 1);
  });
  EXPECT_THROW(duplicate.render(), std::invalid_argument);

  MetricsRegistry short_histogram;
  short_histogram.add_collect_callback([](MetricsSink& sink) {
    sink.histogram("s", "S.", {}, HistogramSnapshot{{1, 2}, {1, 2}, 0});
  });
  EXPECT_THROW(short_histogram.render(), std::invalid_argument);

  MetricsRegistry quantile_label;
  quantile_label.add_collect_callback([](MetricsSink& sink) {
    sink.summary("q", "Q.", {{"quantile", "0.5"}}, SummarySnapshot{{{0.5, 1}}, 1, 1});
  });
  EXPECT_THROW(quantile_label.render(), std::invalid_argument);
  MetricsRegistry quantile_range;
  quantile_range.add_collect_callback([](MetricsSink& sink) {
    sink.summary("q", "Q.", {}, SummarySnapshot{{{1.5, 1}}, 1, 1});
  });
  EXPECT_THROW(quantile_range.render(), std::invalid_argument);
}

TEST(Metrics, ExponentialBuckets) {
  EXPECT_EQ(exponential_buckets(0.001, 2, 4), (std::vector<double>{0.001, 0.002, 0.004, 0.008}));
  EXPECT_THROW(exponential_buckets(0, 2, 4), std::invalid_argument);
  EXPECT_THROW(exponential_buckets(1, 1, 4), std::invalid_argument);
  EXPECT_THROW(exponential_buckets(1, 2, 0), std::invalid_argument);
}

TEST(Metrics, UpdatesFromManyThreadsAreAllCounted) {
  MetricsRegistry registry;
  Counter& counter = registry.counter("n_total", "N.");
  Histogram& histogram = registry.histogram("t", "T.", {0.5});
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&] {
      for (int i = 0; i < 10'000; ++i) {
        counter.inc();
        histogram.observe(1.0);
        if (i % 1000 == 0) registry.render();
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  EXPECT_EQ(counter.value(), 40'000);
  const HistogramSnapshot snapshot = histogram.snapshot();
  EXPECT_EQ(snapshot.bucket_counts, (std::vector<std::uint64_t>{0, 40'000}));
  EXPECT_EQ(snapshot.sum, 40'000);
}

}  // namespace
}  // namespace ricochet::server::metrics_test
