#include "ricochet/loadtest/metrics_scraper.h"

#include <cstdio>
#include <utility>
#include <variant>
#include <vector>

#include "ricochet/loadtest/metrics_client.h"
#include "ricochet/loadtest/prometheus_text.h"

namespace ricochet::loadtest {
namespace {

/// A scrape that has not answered in this long is abandoned (counted unavailable).
constexpr double kScrapeTimeoutS = 5;

}  // namespace

MetricsScraper::MetricsScraper(boost::asio::io_context& io, boost::asio::ip::tcp::endpoint admin,
                               std::string bearer_token, double interval_s, Count count)
    : io_(io),
      admin_(std::move(admin)),
      bearer_token_(std::move(bearer_token)),
      interval_s_(interval_s),
      count_(std::move(count)),
      timer_(io),
      alive_(std::make_shared<bool>(true)) {}

void MetricsScraper::start(std::chrono::steady_clock::time_point start,
                           std::function<void()> on_due, std::function<void(Scrape)> on_scrape) {
  start_ = start;
  on_due_ = std::move(on_due);
  on_scrape_ = std::move(on_scrape);
  schedule();
}

void MetricsScraper::stop() {
  stopped_ = true;
  timer_.cancel();
  alive_.reset();
}

void MetricsScraper::schedule() {
  ++due_;
  const auto offset = std::chrono::microseconds(
      static_cast<std::int64_t>(interval_s_ * static_cast<double>(due_) * 1e6));
  timer_.expires_at(start_ + offset);
  timer_.async_wait([this](const boost::system::error_code& error) {
    if (error || stopped_) return;
    schedule();
    if (on_due_) on_due_();
    if (stopped_) return;                                  // on_due may have ended the run
    if (in_flight_) return count_("metrics_scrape_late");  // the previous one is still out
    if (admin_.port() == 0) {
      // Its directory row advertises no admin port: played on, its figures unknown.
      count_("metrics_not_advertised");
      return on_scrape_(Scrape{});
    }
    in_flight_ = true;
    fetch_metrics(io_, admin_, bearer_token_, kScrapeTimeoutS,
                  [this, alive = std::weak_ptr<bool>(alive_)](MetricsResponse response) {
                    if (alive.expired()) return;
                    in_flight_ = false;
                    on_response(response);
                  });
  });
}

void MetricsScraper::on_response(const MetricsResponse& response) {
  Scrape scrape;
  scrape.elapsed_ms = response.elapsed_ms;
  if (response.status == 401) {
    count_("metrics_unauthorized");
    if (!unauthorized_logged_) {
      unauthorized_logged_ = true;
      std::fprintf(stderr,
                   "ricochet-loadtest: %s:%u refused /metrics (HTTP 401): %s; give the server's "
                   "admin token with --admin-token-file (counted metrics_unauthorized; the run "
                   "goes on without this server's figures)\n",
                   admin_.address().to_string().c_str(), static_cast<unsigned>(admin_.port()),
                   bearer_token_.empty() ? "no token was sent" : "the token sent is not its token");
    }
  } else if (!response.error.empty()) {
    count_("metrics_unavailable");
  } else {
    auto parsed = parse_prometheus_text(response.body);
    if (const auto* problem = std::get_if<std::string>(&parsed)) {
      count_("metrics_malformed");
      std::fprintf(stderr, "ricochet-loadtest: /metrics refused: %s\n", problem->c_str());
    } else {
      scrape.figures = read_server_figures(std::get<std::vector<MetricSample>>(parsed));
    }
  }
  on_scrape_(std::move(scrape));
}

}  // namespace ricochet::loadtest
