#include "admin_http.h"

#include <spdlog/spdlog.h>

#include <array>
#include <atomic>
#include <boost/asio/as_tuple.hpp>
#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/http.hpp>
#include <chrono>
#include <exception>
#include <optional>
#include <string_view>
#include <unordered_set>

namespace ricochet::server {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;

const char* name(AdminRejectReason reason) {
  switch (reason) {
    case AdminRejectReason::Malformed:
      return "malformed";
    case AdminRejectReason::Oversized:
      return "oversized";
    case AdminRejectReason::Timeout:
      return "timeout";
    case AdminRejectReason::NotFound:
      return "not_found";
    case AdminRejectReason::MethodNotAllowed:
      return "method_not_allowed";
    case AdminRejectReason::TooManyConnections:
      return "too_many_connections";
  }
  return "unknown";
}

/// One accepted connection, shared by the coroutine serving it and its watchdog. On the strand.
struct AdminConnection {
  explicit AdminConnection(tcp::socket accepted)
      : socket(std::move(accepted)), watchdog(socket.get_executor()) {}
  tcp::socket socket;
  asio::steady_timer watchdog;  ///< wakes at the deadline, or when cancelled to look again
  proto::TimeUs deadline = 0;   ///< on options.clock: the request read or response written by
  bool timed_out = false;       ///< the watchdog closed the socket at the deadline
  bool served = false;          ///< the serving coroutine is done: the watchdog stops
};

struct AdminHttp::State {
  State(asio::io_context& io, AdminHttpOptions options_in, MetricsRegistry& metrics_in,
        AdminHttpCallbacks callbacks_in)
      : strand(asio::make_strand(io)),
        acceptor(strand),
        options(std::move(options_in)),
        metrics(metrics_in),
        callbacks(std::move(callbacks_in)) {}

  void reject(AdminRejectReason reason) {
    rejected[static_cast<int>(reason)].fetch_add(1, std::memory_order_relaxed);
  }

  asio::strand<asio::io_context::executor_type> strand;
  tcp::acceptor acceptor;  ///< used on the strand only
  const AdminHttpOptions options;
  MetricsRegistry& metrics;
  const AdminHttpCallbacks callbacks;
  std::unordered_set<AdminConnection*> connections;  ///< open ones; on the strand only
  bool stopped = false;                              ///< on the strand only
  std::atomic<std::size_t> open{0};                  ///< connections.size(), for any thread
  std::atomic<std::uint64_t> responses{0};
  std::array<std::atomic<std::uint64_t>, kAdminRejectReasonCount> rejected{};
};

namespace {

using Response = http::response<http::string_body>;
using State = AdminHttp::State;

Response text_response(http::status status, unsigned version, std::string body,
                       std::string_view content_type = "text/plain; charset=utf-8") {
  Response response{status, version};
  response.set(http::field::server, "ricochet-server");
  response.set(http::field::content_type, content_type);
  response.set(http::field::cache_control, "no-store");
  response.body() = std::move(body);
  response.prepare_payload();
  return response;
}

Response route(State& state, const http::request<http::string_body>& request) {
  const unsigned version = request.version();
  std::string_view path{request.target().data(), request.target().size()};
  path = path.substr(0, path.find('?'));
  const bool known = path == "/metrics" || path == "/healthz" || path == "/readyz";
  if (!known) {
    state.reject(AdminRejectReason::NotFound);
    return text_response(http::status::not_found, version,
                         "not found; try /metrics, /healthz or /readyz\n");
  }
  if (request.method() != http::verb::get) {
    state.reject(AdminRejectReason::MethodNotAllowed);
    Response response =
        text_response(http::status::method_not_allowed, version, "only GET is allowed here\n");
    response.set(http::field::allow, "GET");
    return response;
  }
  if (path == "/metrics") {
    try {
      return text_response(http::status::ok, version, state.metrics.render(),
                           kPrometheusContentType);
    } catch (const std::exception& error) {
      spdlog::error("admin http: /metrics failed: {}", error.what());
      return text_response(http::status::internal_server_error, version,
                           std::string{"metrics failed: "} + error.what() + "\n");
    }
  }
  if (path == "/healthz") {
    if (state.callbacks.healthy && state.callbacks.healthy()) {
      return text_response(http::status::ok, version, "ok\n");
    }
    return text_response(http::status::service_unavailable, version, "not ticking on time\n");
  }
  if (state.callbacks.ready && state.callbacks.ready()) {
    return text_response(http::status::ok, version, "ready\n");
  }
  return text_response(http::status::service_unavailable, version, "not ready\n");
}

/// The reply to a request that could not be read, or none (just close).
std::optional<Response> refusal(State& state, const beast::error_code& error) {
  if (error == http::error::header_limit) {
    state.reject(AdminRejectReason::Oversized);
    return text_response(
        http::status::request_header_fields_too_large, 11,
        "request headers above " + std::to_string(state.options.max_request_bytes) + " bytes\n");
  }
  if (error == http::error::body_limit || error == http::error::buffer_overflow) {
    state.reject(AdminRejectReason::Oversized);
    return text_response(
        http::status::payload_too_large, 11,
        "request above " + std::to_string(state.options.max_request_bytes) + " bytes\n");
  }
  if (error.category() == http::make_error_code(http::error::bad_target).category() &&
      error != http::error::partial_message) {
    state.reject(AdminRejectReason::Malformed);
    return text_response(http::status::bad_request, 11, "malformed HTTP request\n");
  }
  return std::nullopt;  // closed or reset by the peer
}

proto::TimeUs deadline_from_now(const State& state) {
  return state.options.clock() +
         std::chrono::duration_cast<std::chrono::microseconds>(state.options.request_timeout)
             .count();
}

/// Closes the connection's socket once options.clock reaches its deadline (the pending read or
/// write then ends with an error). The deadline may move on while it waits.
asio::awaitable<void> watch(std::shared_ptr<State> state,
                            std::shared_ptr<AdminConnection> connection) {
  constexpr auto token = asio::as_tuple(asio::use_awaitable);
  while (!connection->served) {
    const proto::TimeUs left = connection->deadline - state->options.clock();
    if (left <= 0) {
      connection->timed_out = true;
      boost::system::error_code ignored;
      connection->socket.close(ignored);
      co_return;
    }
    connection->watchdog.expires_after(std::chrono::microseconds(left));
    co_await connection->watchdog.async_wait(token);
  }
}

asio::awaitable<void> serve(std::shared_ptr<State> state,
                            std::shared_ptr<AdminConnection> connection) {
  state->connections.insert(connection.get());
  state->open = state->connections.size();
  struct Forget {
    State& state;
    AdminConnection& connection;
    ~Forget() {
      connection.served = true;
      connection.watchdog.cancel();
      state.connections.erase(&connection);
      state.open = state.connections.size();
    }
  } forget{*state, *connection};

  const auto& options = state->options;
  tcp::socket& socket = connection->socket;
  beast::flat_buffer buffer{2 * options.max_request_bytes};
  constexpr auto token = asio::as_tuple(asio::use_awaitable);
  for (;;) {
    http::request_parser<http::string_body> parser;
    parser.header_limit(static_cast<std::uint32_t>(options.max_request_bytes));
    parser.body_limit(options.max_request_bytes);
    const auto [read_error, read_bytes] = co_await http::async_read(socket, buffer, parser, token);
    Response response;
    bool keep_alive = false;
    if (read_error) {
      if (connection->timed_out) {
        state->reject(AdminRejectReason::Timeout);
        break;
      }
      std::optional<Response> reply = refusal(*state, read_error);
      if (!reply) break;
      response = std::move(*reply);
      response.keep_alive(false);
    } else {
      const auto& request = parser.get();
      response = route(*state, request);
      keep_alive = request.keep_alive();
      response.keep_alive(keep_alive);
    }
    connection->deadline = deadline_from_now(*state);
    const auto [write_error, written] = co_await http::async_write(socket, response, token);
    if (write_error) break;
    // The next request's deadline runs from here, before the response is counted: whoever saw
    // the count also sees the deadline.
    connection->deadline = deadline_from_now(*state);
    state->responses.fetch_add(1, std::memory_order_release);
    if (!keep_alive) break;
  }
  boost::system::error_code ignored;
  socket.shutdown(tcp::socket::shutdown_send, ignored);
  socket.close(ignored);
}

asio::awaitable<void> accept_connections(std::shared_ptr<State> state) {
  constexpr auto token = asio::as_tuple(asio::use_awaitable);
  while (!state->stopped) {
    auto [error, socket] = co_await state->acceptor.async_accept(token);
    if (error) {
      if (error == asio::error::operation_aborted || state->stopped) co_return;
      spdlog::warn("admin http: accept failed: {}", error.message());
      continue;
    }
    if (static_cast<int>(state->connections.size()) >= state->options.max_connections) {
      state->reject(AdminRejectReason::TooManyConnections);
      boost::system::error_code ignored;
      socket.close(ignored);
      continue;
    }
    auto connection = std::make_shared<AdminConnection>(std::move(socket));
    connection->deadline = deadline_from_now(*state);
    asio::co_spawn(state->strand, serve(state, connection), asio::detached);
    asio::co_spawn(state->strand, watch(state, std::move(connection)), asio::detached);
  }
}

}  // namespace

AdminHttp::AdminHttp(asio::io_context& io, AdminHttpOptions options, MetricsRegistry& metrics,
                     AdminHttpCallbacks callbacks)
    : state_(std::make_shared<State>(io, std::move(options), metrics, std::move(callbacks))) {
  std::weak_ptr<State> weak = state_;
  metrics.add_collect_callback([weak](MetricsSink& sink) {
    const std::shared_ptr<State> state = weak.lock();
    if (!state) return;
    sink.counter("ricochet_admin_responses_total", "Admin HTTP responses sent (any status).", {},
                 static_cast<double>(state->responses.load(std::memory_order_relaxed)));
    for (std::size_t i = 0; i < kAdminRejectReasonCount; ++i) {
      sink.counter("ricochet_admin_rejected_total",
                   "Admin HTTP requests and connections refused, by reason.",
                   {{"reason", name(static_cast<AdminRejectReason>(i))}},
                   static_cast<double>(state->rejected[i].load(std::memory_order_relaxed)));
    }
  });
}

AdminHttp::~AdminHttp() {
  stop();
}

boost::system::error_code AdminHttp::start() {
  boost::system::error_code error;
  const asio::ip::address address = asio::ip::make_address(state_->options.bind, error);
  if (error) return error;
  const tcp::endpoint wanted{address, state_->options.port};
  tcp::acceptor& acceptor = state_->acceptor;
  acceptor.open(wanted.protocol(), error);
  if (!error) acceptor.set_option(tcp::acceptor::reuse_address(true), error);
  if (!error) acceptor.bind(wanted, error);
  if (!error) acceptor.listen(asio::socket_base::max_listen_connections, error);
  if (error) {
    boost::system::error_code ignored;
    acceptor.close(ignored);
    return error;
  }
  endpoint_ = acceptor.local_endpoint(error);
  if (error) return error;
  asio::co_spawn(state_->strand, accept_connections(state_), asio::detached);
  return {};
}

void AdminHttp::stop() {
  asio::post(state_->strand, [state = state_] {
    if (state->stopped) return;
    state->stopped = true;
    boost::system::error_code ignored;
    state->acceptor.close(ignored);
    for (AdminConnection* connection : state->connections) connection->socket.close(ignored);
  });
}

void AdminHttp::check_deadlines() {
  asio::post(state_->strand, [state = state_] {
    for (AdminConnection* connection : state->connections) connection->watchdog.cancel();
  });
}

std::size_t AdminHttp::connections() const {
  return state_->open.load();
}

std::uint64_t AdminHttp::responses() const {
  return state_->responses.load(std::memory_order_acquire);
}

std::uint64_t AdminHttp::rejected(AdminRejectReason reason) const {
  return state_->rejected[static_cast<int>(reason)].load(std::memory_order_relaxed);
}

}  // namespace ricochet::server
