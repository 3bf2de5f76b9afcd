#pragma once
/// The load test's and the soak's clock of /metrics scrapes: one every `interval_s` on a fixed
/// schedule (the n-th at start + n × interval, so a slow scrape never shifts the later ones), at
/// most one request out at a time (a scrape due while the previous one is out is skipped and
/// counted `metrics_scrape_late`), each answer parsed into ServerFigures (no answer is counted
/// `metrics_unavailable`, a 401 for want of the admin token `metrics_unauthorized` and logged
/// once, a malformed one `metrics_malformed` and logged). A server with no admin port (port 0: its
/// fleet directory row advertises none) is never asked: each due scrape completes with no
/// figures, counted `metrics_not_advertised`.

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "ricochet/loadtest/metrics_client.h"
#include "ricochet/loadtest/server_figures.h"

namespace ricochet::loadtest {

class MetricsScraper {
 public:
  /// One completed request.
  struct Scrape {
    double elapsed_ms = 0;                 ///< the request's round trip
    std::optional<ServerFigures> figures;  ///< empty when there was no usable answer (counted)
  };
  /// Counts a failure by kind into the run's error table.
  using Count = std::function<void(const std::string& kind)>;

  /// `bearer_token`: sent on every request (the server's admin token); empty: none.
  MetricsScraper(boost::asio::io_context& io, boost::asio::ip::tcp::endpoint admin,
                 std::string bearer_token, double interval_s, Count count);
  MetricsScraper(const MetricsScraper&) = delete;
  MetricsScraper& operator=(const MetricsScraper&) = delete;

  /// Starts the schedule: the first scrape is due at `start` + one interval. `on_due` runs at
  /// every due time, before the request (the soak's churn rides on it); `on_scrape` runs when a
  /// request completes. Both on the io_context.
  void start(std::chrono::steady_clock::time_point start, std::function<void()> on_due,
             std::function<void(Scrape)> on_scrape);
  /// Stops the schedule; a request in flight completes into nothing.
  void stop();

 private:
  void schedule();
  void on_response(const MetricsResponse& response);

  boost::asio::io_context& io_;
  boost::asio::ip::tcp::endpoint admin_;
  std::string bearer_token_;
  double interval_s_;
  Count count_;
  std::function<void()> on_due_;
  std::function<void(Scrape)> on_scrape_;
  std::chrono::steady_clock::time_point start_;
  boost::asio::steady_timer timer_;
  std::uint64_t due_ = 0;  ///< scrapes scheduled so far
  bool in_flight_ = false;
  bool stopped_ = false;
  bool unauthorized_logged_ = false;
  std::shared_ptr<bool> alive_;  ///< a request's callback holds a weak_ptr
};

}  // namespace ricochet::loadtest
