#include "ricochet/loadtest/metrics_client.h"

#include <boost/asio/read.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>
#include <charconv>
#include <chrono>
#include <memory>

#include "ricochet/loadtest/prometheus_text.h"

namespace ricochet::loadtest {

namespace asio = boost::asio;

namespace {

class MetricsFetch : public std::enable_shared_from_this<MetricsFetch> {
 public:
  MetricsFetch(asio::io_context& io, std::string path, std::size_t max_bytes,
               std::function<void(MetricsResponse)> done)
      : path_(std::move(path)),
        max_bytes_(max_bytes),
        socket_(io),
        timer_(io),
        done_(std::move(done)),
        started_(std::chrono::steady_clock::now()) {}

  void start(const asio::ip::tcp::endpoint& admin, const std::string& bearer_token,
             double timeout_s) {
    request_ = "GET " + path_ + " HTTP/1.0\r\nHost: 127.0.0.1\r\n";
    if (!bearer_token.empty()) request_ += "Authorization: Bearer " + bearer_token + "\r\n";
    request_ += "Connection: close\r\n\r\n";
    timer_.expires_after(std::chrono::microseconds(static_cast<std::int64_t>(timeout_s * 1e6)));
    timer_.async_wait([self = shared_from_this()](const boost::system::error_code& error) {
      if (!error) self->finish("timed out");
    });
    socket_.async_connect(admin, [self = shared_from_this()](const boost::system::error_code& e) {
      if (e) return self->finish("cannot connect: " + e.message());
      self->send();
    });
  }

 private:
  void send() {
    asio::async_write(socket_, asio::buffer(request_),
                      [self = shared_from_this()](const boost::system::error_code& e, std::size_t) {
                        if (e) return self->finish("cannot send the request: " + e.message());
                        self->read();
                      });
  }

  void read() {
    socket_.async_read_some(
        asio::buffer(chunk_),
        [self = shared_from_this()](const boost::system::error_code& e, std::size_t size) {
          self->text_.append(self->chunk_.data(), size);
          if (self->text_.size() > self->max_bytes_ + 4096) {
            return self->finish("the response is larger than the " +
                                std::to_string(self->max_bytes_ >> 20) + " MiB accepted");
          }
          if (e == asio::error::eof) return self->parse();
          if (e) return self->finish("cannot read the response: " + e.message());
          self->read();
        });
  }

  void parse() {
    const std::size_t header_end = text_.find("\r\n\r\n");
    if (text_.rfind("HTTP/1.", 0) != 0 || header_end == std::string::npos || text_.size() < 12) {
      return finish("the response is not HTTP");
    }
    const std::string status = text_.substr(9, 3);
    int code = 0;
    std::from_chars(status.data(), status.data() + status.size(), code);
    if (status != "200") return finish("HTTP " + status + " from " + path_, code);
    MetricsResponse response;
    response.status = code;
    response.body = text_.substr(header_end + 4);
    deliver(std::move(response));
  }

  void finish(std::string error, int status = 0) {
    MetricsResponse response;
    response.error = std::move(error);
    response.status = status;
    deliver(std::move(response));
  }

  void deliver(MetricsResponse response) {
    if (!done_) return;
    boost::system::error_code ignored;
    timer_.cancel();
    socket_.close(ignored);
    response.elapsed_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started_)
            .count();
    auto done = std::move(done_);
    done_ = nullptr;
    done(std::move(response));
  }

  std::string path_;
  std::size_t max_bytes_;
  std::string request_;
  asio::ip::tcp::socket socket_;
  asio::steady_timer timer_;
  std::function<void(MetricsResponse)> done_;
  std::chrono::steady_clock::time_point started_;
  std::array<char, 65536> chunk_{};
  std::string text_;
};

}  // namespace

void fetch_metrics(asio::io_context& io, const asio::ip::tcp::endpoint& admin,
                   const std::string& bearer_token, double timeout_s,
                   std::function<void(MetricsResponse)> done) {
  fetch_admin(io, admin, "/metrics", kMaxMetricsBytes, bearer_token, timeout_s, std::move(done));
}

void fetch_admin(asio::io_context& io, const asio::ip::tcp::endpoint& admin, std::string path,
                 std::size_t max_bytes, const std::string& bearer_token, double timeout_s,
                 std::function<void(MetricsResponse)> done) {
  std::make_shared<MetricsFetch>(io, std::move(path), max_bytes, std::move(done))
      ->start(admin, bearer_token, timeout_s);
}

}  // namespace ricochet::loadtest
