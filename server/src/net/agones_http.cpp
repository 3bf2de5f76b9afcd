#include "agones_http.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <boost/asio/as_tuple.hpp>
#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/http.hpp>
#include <charconv>
#include <stdexcept>
#include <string>
#include <utility>

#include "steady_time.h"

namespace ricochet::server {

namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;

/// The sidecar answers `{}`, or the GameServer to GET /gameserver (a few KiB).
constexpr std::uint64_t kMaxAnswerBytes = 64 * 1024;

AgonesOutcome outcome_of(const boost::system::error_code& error) {
  return error == beast::error::timeout ? AgonesOutcome::Timeout : AgonesOutcome::IoError;
}

}  // namespace

std::uint16_t parse_agones_sdk_port(std::string_view text) {
  unsigned port = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), port);
  if (text.empty() || error != std::errc{} || end != text.data() + text.size() || port == 0 ||
      port > 65535) {
    throw std::runtime_error(
        "AGONES_SDK_HTTP_PORT must be the Agones SDK sidecar's port "
        "(1..65535), got \"" +
        std::string(text) + "\"");
  }
  return static_cast<std::uint16_t>(port);
}

AgonesHttp::AgonesHttp(AgonesHttpOptions options, MetricsRegistry& metrics)
    : options_(std::move(options)), sdk_(options_.sdk) {
  for (std::size_t call = 0; call < kAgonesCallCount; ++call) {
    for (std::size_t outcome = 0; outcome < kAgonesOutcomeCount; ++outcome) {
      calls_[call][outcome] = &metrics.counter(
          "ricochet_agones_calls_total", "Calls to the Agones SDK sidecar, by call and outcome",
          {{"call", name(static_cast<AgonesCall>(call))},
           {"outcome", name(static_cast<AgonesOutcome>(outcome))}});
    }
  }
  health_withheld_ = &metrics.counter(
      "ricochet_agones_health_withheld_total",
      "Agones health pings not sent because a match was stuck or overran its catch-up cap");
  if (options_.game_server) sdk_.fetch_game_server();
  asio::co_spawn(io_, run(), asio::detached);
  thread_ = std::thread([this] { io_.run(); });
}

AgonesHttp::~AgonesHttp() {
  io_.stop();
  thread_.join();
}

void AgonesHttp::post_event(std::function<void(AgonesSdk&, proto::TimeUs now)> event) {
  asio::post(io_, [this, event = std::move(event)] {
    event(sdk_, steady_now_us());
    wake_.cancel();
  });
}

void AgonesHttp::ready() {
  post_event([](AgonesSdk& sdk, proto::TimeUs now) { sdk.ready(now); });
}
void AgonesHttp::players_placed() {
  post_event([](AgonesSdk& sdk, proto::TimeUs) { sdk.players_placed(); });
}
void AgonesHttp::match_finished() {
  post_event([](AgonesSdk& sdk, proto::TimeUs) { sdk.match_finished(); });
}
void AgonesHttp::stopping() {
  post_event([](AgonesSdk& sdk, proto::TimeUs) { sdk.stopping(); });
}

bool AgonesHttp::drained(std::chrono::milliseconds limit) {
  post_event([](AgonesSdk& sdk, proto::TimeUs) { sdk.drained(); });
  std::unique_lock lock(finished_mutex_);
  return finished_changed_.wait_for(lock, limit, [this] { return finished_; });
}

void AgonesHttp::publish_counters() {
  const std::uint64_t withheld = sdk_.counters().health_withheld;
  if (withheld > withheld_published_) {
    health_withheld_->inc(static_cast<double>(withheld - withheld_published_));
    withheld_published_ = withheld;
  }
  if (sdk_.finished()) {
    const std::lock_guard lock(finished_mutex_);
    finished_ = true;
    finished_changed_.notify_all();
  }
}

asio::awaitable<void> AgonesHttp::run() {
  for (;;) {
    proto::TimeUs now = steady_now_us();
    sdk_.observe(options_.matches());
    std::optional<AgonesRequest> request = sdk_.next_call(now);
    publish_counters();
    if (request) {
      const auto [outcome, body] = co_await perform(*request);
      calls_[static_cast<std::size_t>(request->call)][static_cast<std::size_t>(outcome)]->inc();
      sdk_.call_done(outcome, steady_now_us(), body);
      if (auto answer = sdk_.take_game_server(); answer && options_.game_server) {
        options_.game_server(std::move(answer->body));
      }
      publish_counters();
      continue;
    }
    auto wait = options_.poll_interval;
    if (const auto due = sdk_.next_due(now)) {
      const auto until_due = std::chrono::duration_cast<std::chrono::milliseconds>(
          std::chrono::microseconds(*due - now));
      wait = std::clamp(until_due, std::chrono::milliseconds(1), wait);
    }
    wake_.expires_after(wait);
    co_await wake_.async_wait(asio::as_tuple(asio::use_awaitable));  // or an event cancels it
  }
}

asio::awaitable<std::pair<AgonesOutcome, std::string>> AgonesHttp::perform(
    const AgonesRequest& request) {
  constexpr auto token = asio::as_tuple(asio::use_awaitable);
  beast::tcp_stream stream(co_await asio::this_coro::executor);
  stream.expires_after(options_.call_timeout);
  const auto [connect_error] = co_await stream.async_connect(
      tcp::endpoint(asio::ip::address_v4::loopback(), options_.port), token);
  if (connect_error) co_return std::pair{outcome_of(connect_error), std::string()};

  const http::verb verb = request.method == "PUT"   ? http::verb::put
                          : request.method == "GET" ? http::verb::get
                                                    : http::verb::post;
  http::request<http::string_body> message{verb, request.path, 11};
  message.set(http::field::host, "localhost:" + std::to_string(options_.port));
  if (verb != http::verb::get) message.set(http::field::content_type, "application/json");
  message.set(http::field::connection, "close");
  message.body() = request.body;
  message.prepare_payload();
  const auto [write_error, written] = co_await http::async_write(stream, message, token);
  if (write_error) co_return std::pair{outcome_of(write_error), std::string()};

  beast::flat_buffer buffer;
  http::response_parser<http::string_body> parser;
  parser.body_limit(kMaxAnswerBytes);
  const auto [read_error, read] = co_await http::async_read(stream, buffer, parser, token);
  if (read_error) co_return std::pair{outcome_of(read_error), std::string()};
  boost::system::error_code ignored;
  stream.socket().shutdown(tcp::socket::shutdown_both, ignored);

  const unsigned status = parser.get().result_int();
  if (status >= 200 && status < 300)
    co_return std::pair{AgonesOutcome::Ok, parser.release().body()};
  if (status >= 500) co_return std::pair{AgonesOutcome::ServerError, std::string()};
  spdlog::debug("agones: {} {} answered {}: {}", request.method, request.path, status,
                parser.get().body());
  co_return std::pair{AgonesOutcome::ClientError, std::string()};
}

}  // namespace ricochet::server
