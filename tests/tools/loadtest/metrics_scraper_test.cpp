// MetricsScraper (metrics_scraper.h) on a server whose --fleet row advertises no admin port: never
// asked, each due scrape completes with no figures, counted metrics_not_advertised.

#include "ricochet/loadtest/metrics_scraper.h"

#include <gtest/gtest.h>

#include <boost/asio/ip/address.hpp>
#include <string>
#include <vector>

namespace ricochet::loadtest::metrics_scraper_test {
namespace {

TEST(MetricsScraper, AServerWithoutAnAdminPortIsCountedNotAsked) {
  boost::asio::io_context io;
  std::vector<std::string> kinds;
  MetricsScraper scraper(io, {boost::asio::ip::make_address("127.0.0.1"), 0}, "", 1.0,
                         [&](const std::string& kind) { kinds.push_back(kind); });
  int scrapes = 0;
  bool figures = false;
  // Started one interval ago: the first scrape is due at once.
  scraper.start(std::chrono::steady_clock::now() - std::chrono::seconds(1), nullptr,
                [&](MetricsScraper::Scrape scrape) {
                  ++scrapes;
                  figures = scrape.figures.has_value();
                  scraper.stop();
                });
  io.run();  // returns once stopped: nothing else is waited for
  EXPECT_EQ(scrapes, 1);
  EXPECT_FALSE(figures);
  EXPECT_EQ(kinds, std::vector<std::string>{"metrics_not_advertised"});
}

}  // namespace
}  // namespace ricochet::loadtest::metrics_scraper_test
