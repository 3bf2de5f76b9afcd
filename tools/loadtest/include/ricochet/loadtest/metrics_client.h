#pragma once
/// GET /metrics (or another path: /fleet) from the server's admin HTTP port on the load test's
/// io_context: connect, one HTTP/1.0 request, read to the end, within a deadline. Never blocks
/// the loop.

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <functional>
#include <string>

namespace ricochet::loadtest {

struct MetricsResponse {
  std::string body;   ///< the exposition text (or /fleet's JSON), when error is empty
  std::string error;  ///< why there is no body ("connection refused", "HTTP 503", "timed out")
  int status = 0;     ///< the HTTP status; 0: no HTTP response
  double elapsed_ms = 0;
};

/// Calls `done` once, on `io`, with the body of GET /metrics or the reason there is none.
/// `timeout_s` > 0; the body is refused beyond kMaxMetricsBytes. A `bearer_token` (printable
/// ASCII: admin_token.h) goes in an `Authorization: Bearer` header; empty: none.
void fetch_metrics(boost::asio::io_context& io, const boost::asio::ip::tcp::endpoint& admin,
                   const std::string& bearer_token, double timeout_s,
                   std::function<void(MetricsResponse)> done);
/// The same for GET `path` ("/fleet"), the body refused beyond `max_bytes`.
void fetch_admin(boost::asio::io_context& io, const boost::asio::ip::tcp::endpoint& admin,
                 std::string path, std::size_t max_bytes, const std::string& bearer_token,
                 double timeout_s, std::function<void(MetricsResponse)> done);

}  // namespace ricochet::loadtest
