#include "ricochet/loadtest/prometheus_text.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "ricochet/loadtest/server_figures.h"

namespace ricochet::loadtest::prometheus_text_test {
namespace {

std::vector<MetricSample> parse_ok(std::string_view text) {
  auto parsed = parse_prometheus_text(text);
  if (const auto* error = std::get_if<std::string>(&parsed)) {
    ADD_FAILURE() << *error;
    return {};
  }
  return std::get<std::vector<MetricSample>>(parsed);
}

std::string parse_error(std::string_view text) {
  auto parsed = parse_prometheus_text(text);
  if (const auto* error = std::get_if<std::string>(&parsed)) return *error;
  return {};
}

TEST(PrometheusText, ReadsSamplesLabelsAndSpecialValues) {
  const auto samples = parse_ok(
      "# HELP a_total Things\n# TYPE a_total counter\na_total 12\n"
      "b{x=\"1\",y=\"q\\\"uote\\\\\\n\"} 2.5e-3 1700000000000\r\n\n"
      "c +Inf\nd{} NaN\n");
  ASSERT_EQ(samples.size(), 4u);
  EXPECT_EQ(samples[0].name, "a_total");
  EXPECT_EQ(samples[0].value, 12);
  EXPECT_EQ(samples[1].label("x"), "1");
  EXPECT_EQ(samples[1].label("y"), "q\"uote\\\n");
  EXPECT_EQ(samples[1].label("z"), "");
  EXPECT_DOUBLE_EQ(samples[1].value, 0.0025);
  EXPECT_TRUE(std::isinf(samples[2].value));
  EXPECT_TRUE(std::isnan(samples[3].value));
}

TEST(PrometheusText, RefusesMalformedLinesNamingTheLine) {
  EXPECT_EQ(parse_error("ok 1\n9bad 1\n"), "line 2: expected a metric name at column 1");
  EXPECT_EQ(parse_error("a{x=1} 2\n"), "line 1: expected '\"' opening the label value at column 5");
  EXPECT_EQ(parse_error("a{x=\"1\" 2\n"), "line 1: expected ',' or '}' after a label at column 8");
  EXPECT_EQ(parse_error("a{x=\"1} 2\n"), "line 1: unterminated label value at column 10");
  EXPECT_EQ(parse_error("a 1e999\n"),
            "line 1: expected a number (or +Inf, -Inf, NaN) as the value at column 8");
  EXPECT_EQ(parse_error("a\n"), "line 1: expected a space before the value at column 2");
  EXPECT_EQ(parse_error("a 1 2 x\n"), "line 1: unexpected text after the value at column 7");
  EXPECT_FALSE(parse_error(std::string(kMaxMetricsBytes + 1, '#')).empty());
  std::string many = "a{";
  for (int i = 0; i < 17; ++i) many += std::string("l") + std::to_string(i) + "=\"v\",";
  EXPECT_NE(parse_error(many + "} 1\n").find("more than 16 labels"), std::string::npos);
}

TEST(ServerFigures, ReadsTheMatchesQuantilesOverrunsAndTraffic) {
  const auto samples = parse_ok(
      "ricochet_process_id 4242\nricochet_matches 2\nricochet_players 5\n"
      "ricochet_tick_seconds{match=\"1\",quantile=\"0.5\"} 0.0001\n"
      "ricochet_tick_seconds{match=\"1\",quantile=\"0.99\"} 0.002\n"
      "ricochet_tick_seconds{match=\"1\",quantile=\"1\"} 0.003\n"
      "ricochet_tick_seconds{match=\"2\",quantile=\"0.99\"} 0.009\n"
      "ricochet_tick_seconds{match=\"x\",quantile=\"0.99\"} 1\n"
      "ricochet_match_players{match=\"1\",state=\"connected\"} 5\n"
      "ricochet_match_players{match=\"2\",state=\"connected\"} 0\n"
      "ricochet_match_overruns_total{match=\"1\"} 3\nricochet_match_overruns_total{match=\"2\"} 1\n"
      "ricochet_game_packets_total{direction=\"in\"} 100\n"
      "ricochet_game_packets_total{direction=\"out\"} 90\n"
      "ricochet_game_dropped_total{reason=\"a\"} 1\nricochet_game_dropped_total{reason=\"b\"} 2\n"
      "ricochet_tick_phase_seconds_sum{match=\"1\",phase=\"physics\"} 0.5\n"
      "ricochet_tick_phase_seconds_sum{match=\"2\",phase=\"physics\"} 0.25\n"
      "ricochet_tick_phase_seconds_count{match=\"2\",phase=\"physics\"} 100\n");
  const ServerFigures figures = read_server_figures(samples);
  EXPECT_EQ(figures.pid, 4242);
  EXPECT_EQ(figures.matches, 2);
  EXPECT_EQ(figures.players, 5);
  EXPECT_EQ(figures.overruns, 4);
  EXPECT_EQ(figures.packets_in, 100);
  EXPECT_EQ(figures.packets_out, 90);
  EXPECT_EQ(figures.game_dropped, 3);
  EXPECT_EQ(figures.phase_seconds, (std::map<std::string, double>{{"physics", 0.75}}));
  ASSERT_EQ(figures.by_match.size(), 2u);  // the match labelled "x" is skipped
  // Match 2 has nobody connected: its slow ticks are not the players'.
  const TickQuantiles worst = figures.worst_tick();
  EXPECT_DOUBLE_EQ(worst.p50_ms, 0.1);
  EXPECT_DOUBLE_EQ(worst.p95_ms, 0);  // not reported
  EXPECT_DOUBLE_EQ(worst.p99_ms, 2.0);
  EXPECT_DOUBLE_EQ(worst.max_ms, 3.0);
  // The process figures a soak follows are absent here: not read as zero.
  EXPECT_EQ(figures.open_fds, -1);
  EXPECT_EQ(figures.resident_bytes, -1);
  EXPECT_EQ(figures.db_bytes, -1);
}

TEST(ServerFigures, ReadsTheProcessFiguresASoakFollows) {
  const ServerFigures figures =
      read_server_figures(parse_ok("process_open_fds 57\nprocess_resident_memory_bytes 9.4e+07\n"
                                   "ricochet_db_file_bytes 131072\n"));
  EXPECT_EQ(figures.open_fds, 57);
  EXPECT_EQ(figures.resident_bytes, 9.4e7);
  EXPECT_EQ(figures.db_bytes, 131072);
}

TEST(ServerFigures, ReadsThePlacementTicketsByResult) {
  const ServerFigures figures = read_server_figures(
      parse_ok("ricochet_placement_tickets_total{result=\"assigned\"} 14\n"
               "ricochet_placement_tickets_total{result=\"no_server_available\"} 2\n"
               "ricochet_placement_tickets_total{result=\"failed\"} -3\n"
               "ricochet_placement_tickets_total 5\n"));
  EXPECT_EQ(figures.placement_tickets,
            (std::map<std::string, double>{{"assigned", 14}, {"no_server_available", 2}}));
  EXPECT_EQ(figures.bad_values, 1);  // the negative count, left out
}

}  // namespace
}  // namespace ricochet::loadtest::prometheus_text_test
