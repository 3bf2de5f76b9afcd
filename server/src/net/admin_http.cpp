#include "admin_http.h"

#include <spdlog/spdlog.h>

#include <algorithm>
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
#include <variant>

#include "ricochet/proto/address.h"

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
    case AdminRejectReason::TooManyFromAddress:
      return "too_many_from_address";
    case AdminRejectReason::Unauthorized:
      return "unauthorized";
    case AdminRejectReason::Forbidden:
      return "forbidden";
  }
  return "unknown";
}

/// One accepted connection, shared by the coroutine serving it and its watchdog. On the strand.
struct AdminConnection {
  AdminConnection(tcp::socket accepted, proto::HostKey peer)
      : socket(std::move(accepted)), watchdog(socket.get_executor()), host(peer) {}
  tcp::socket socket;
  asio::steady_timer watchdog;  ///< wakes at the deadline, or when cancelled to look again
  proto::TimeUs deadline = 0;   ///< on options.clock: the request read or response written by
  bool timed_out = false;       ///< the watchdog closed the socket at the deadline
  bool served = false;          ///< the serving coroutine is done: the watchdog stops
  proto::HostKey host;          ///< the peer, as the per-address cap counts it
  bool reading = true;          ///< waiting for a request (not answering one)
  /// When it began waiting for a request, as State::waits counts: smaller waited longer.
  std::uint64_t waiting_since = 0;
  bool evicted = false;  ///< closed to make room for a newer connection; no longer counted
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
  std::uint64_t waits = 0;           ///< waits for a request begun so far; on the strand only
  std::atomic<std::size_t> open{0};  ///< connections.size(), for any thread
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

/// Equal texts, in a time that depends on their lengths only, not on where they differ.
bool same_secret(std::string_view given, std::string_view expected) {
  unsigned difference = given.size() == expected.size() ? 0U : 1U;
  for (std::size_t i = 0; i < given.size(); ++i) {
    const char other = expected.empty() ? '\0' : expected[i % expected.size()];
    difference |= static_cast<unsigned char>(given[i] ^ other);
  }
  return difference == 0;
}

bool authorized(const State& state, const http::request<http::string_body>& request) {
  const std::string& token = state.options.bearer_token;
  if (token.empty()) return true;
  const auto header = request.find(http::field::authorization);
  if (header == request.end()) return false;
  const std::string_view value{header->value().data(), header->value().size()};
  constexpr std::string_view kScheme = "Bearer ";
  if (value.size() < kScheme.size() || value.substr(0, kScheme.size()) != kScheme) return false;
  return same_secret(value.substr(kScheme.size()), token);
}

/// The peer's proto::HostKey (IPv4-mapped IPv6 counts as its IPv4 address).
proto::HostKey host_key_of(const tcp::socket& socket) {
  boost::system::error_code error;
  const tcp::endpoint peer = socket.remote_endpoint(error);
  proto::Address address;
  if (!error && peer.address().is_v4()) {
    const auto bytes = peer.address().to_v4().to_bytes();
    std::copy(bytes.begin(), bytes.end(), address.ip.begin());
  } else if (!error) {
    const auto bytes = peer.address().to_v6().to_bytes();
    std::copy(bytes.begin(), bytes.end(), address.ip.begin());
    address.v6 = true;
  }
  return proto::host_key(address);
}

/// "/accounts/<name>/ban" or "/accounts/<name>/unban" as an action (no operator yet), or nothing.
std::optional<AccountAction> account_path(std::string_view path) {
  constexpr std::string_view kPrefix = "/accounts/";
  if (path.substr(0, kPrefix.size()) != kPrefix) return std::nullopt;
  path.remove_prefix(kPrefix.size());
  const auto slash = path.find('/');
  if (slash == std::string_view::npos) return std::nullopt;
  const std::string_view username = path.substr(0, slash);
  const std::string_view verb = path.substr(slash + 1);
  constexpr std::size_t kMaxName = 64;
  const bool name_ok = !username.empty() && username.size() <= kMaxName &&
                       std::all_of(username.begin(), username.end(), [](char c) {
                         return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                                (c >= '0' && c <= '9') || c == '_' || c == '.' || c == '-';
                       });
  if (!name_ok || (verb != "ban" && verb != "unban")) return std::nullopt;
  return AccountAction{std::string(username), verb == "ban", {}};
}

bool loopback_only(const State& state) {
  boost::system::error_code error;
  const asio::ip::address bound = asio::ip::make_address(state.options.bind, error);
  return !error && bound.is_loopback();
}

/// The 401 of a request without the bearer token, logged once per episode per address.
Response unauthorized(State& state, const AdminConnection& connection, unsigned version,
                      std::string_view what) {
  state.reject(AdminRejectReason::Unauthorized);
  const std::string detail = std::string(what) + " without the admin bearer token";
  if (state.options.episodes) {
    state.options.episodes->refuse(name(AdminRejectReason::Unauthorized),
                                   connection.host.to_string(), detail, state.options.clock());
  }
  Response response = text_response(http::status::unauthorized, version,
                                    std::string(what) + " needs Authorization: Bearer <token>\n");
  response.set(http::field::www_authenticate, "Bearer");
  return response;
}

/// GET /fleet, authorized: the fleet callback answers it.
struct FleetRequest {};

/// What a request gets: a response now, or an account action or the fleet to ask first.
using Routed = std::variant<Response, AccountAction, FleetRequest>;

Routed route_account(State& state, const AdminConnection& connection,
                     const http::request<http::string_body>& request, AccountAction action) {
  const unsigned version = request.version();
  if (request.method() != http::verb::post) {
    state.reject(AdminRejectReason::MethodNotAllowed);
    Response response =
        text_response(http::status::method_not_allowed, version, "only POST is allowed here\n");
    response.set(http::field::allow, "POST");
    return response;
  }
  if (state.options.bearer_token.empty() && !loopback_only(state)) {
    state.reject(AdminRejectReason::Forbidden);
    if (state.options.episodes) {
      state.options.episodes->refuse(name(AdminRejectReason::Forbidden),
                                     connection.host.to_string(),
                                     "an account action on an admin port bound to " +
                                         state.options.bind + " without admin.token_file",
                                     state.options.clock());
    }
    return text_response(http::status::forbidden, version,
                         "account actions need admin.token_file when the admin port is not "
                         "bound to a loopback address\n");
  }
  if (!authorized(state, request)) return unauthorized(state, connection, version, "/accounts");
  action.operator_address = connection.host.to_string();
  return action;
}

Routed route(State& state, const AdminConnection& connection,
             const http::request<http::string_body>& request) {
  const unsigned version = request.version();
  std::string_view path{request.target().data(), request.target().size()};
  path = path.substr(0, path.find('?'));
  if (auto action = state.callbacks.account ? account_path(path) : std::nullopt) {
    return route_account(state, connection, request, std::move(*action));
  }
  const bool fleet = path == "/fleet" && state.callbacks.fleet;
  const bool known = path == "/metrics" || path == "/healthz" || path == "/readyz" || fleet;
  if (!known) {
    state.reject(AdminRejectReason::NotFound);
    return text_response(http::status::not_found, version,
                         state.callbacks.fleet
                             ? "not found; try /metrics, /healthz, /readyz or /fleet\n"
                             : "not found; try /metrics, /healthz or /readyz\n");
  }
  if (request.method() != http::verb::get) {
    state.reject(AdminRejectReason::MethodNotAllowed);
    Response response =
        text_response(http::status::method_not_allowed, version, "only GET is allowed here\n");
    response.set(http::field::allow, "GET");
    return response;
  }
  if (path == "/metrics") {
    if (!authorized(state, request)) return unauthorized(state, connection, version, "/metrics");
    try {
      return text_response(http::status::ok, version, state.metrics.render(),
                           kPrometheusContentType);
    } catch (const std::exception& error) {
      spdlog::error("admin http: /metrics failed: {}", error.what());
      return text_response(http::status::internal_server_error, version,
                           std::string{"metrics failed: "} + error.what() + "\n");
    }
  }
  if (fleet) {
    if (!authorized(state, request)) return unauthorized(state, connection, version, "/fleet");
    return FleetRequest{};
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

/// Runs `ask` (a callback given where to answer) and resumes on the strand with its reply.
asio::awaitable<AdminReply> await_reply(std::shared_ptr<State> state,
                                        std::function<void(std::function<void(AdminReply)>)> ask) {
  struct Pending {
    explicit Pending(const asio::any_io_executor& executor) : wake(executor) {}
    std::optional<AdminReply> reply;
    asio::steady_timer wake;
  };
  auto pending = std::make_shared<Pending>(state->strand);
  pending->wake.expires_at(asio::steady_timer::time_point::max());
  ask([state, pending](AdminReply reply) {
    asio::post(state->strand, [pending, reply = std::move(reply)]() mutable {
      pending->reply = std::move(reply);
      pending->wake.cancel();
    });
  });
  while (!pending->reply) {
    co_await pending->wake.async_wait(asio::as_tuple(asio::use_awaitable));
  }
  co_return std::move(*pending->reply);
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
    connection->reading = true;
    connection->waiting_since = ++state->waits;
    const auto [read_error, read_bytes] = co_await http::async_read(socket, buffer, parser, token);
    connection->reading = false;
    if (connection->evicted) break;
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
      Routed routed = route(*state, *connection, request);
      std::function<void(std::function<void(AdminReply)>)> ask;
      if (auto* action = std::get_if<AccountAction>(&routed)) {
        ask = [state, action = std::move(*action)](std::function<void(AdminReply)> answer) {
          state->callbacks.account(action, std::move(answer));
        };
      } else if (std::holds_alternative<FleetRequest>(routed)) {
        ask = state->callbacks.fleet;
      }
      if (ask) {
        // The answer and its response within request_timeout, as any response.
        connection->deadline = deadline_from_now(*state);
        AdminReply reply = co_await await_reply(state, std::move(ask));
        routed = text_response(static_cast<http::status>(reply.status), request.version(),
                               std::move(reply.body), reply.content_type);
      }
      response = std::move(std::get<Response>(routed));
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

/// Closes the connection among `among` (open, not evicted) that has waited longest for a
/// request; false when every one is busy answering.
template <class Among>
bool evict_longest_waiting(State& state, Among among) {
  AdminConnection* longest = nullptr;
  for (AdminConnection* connection : state.connections) {
    if (connection->evicted || !connection->reading || !among(*connection)) continue;
    if (!longest || connection->waiting_since < longest->waiting_since) longest = connection;
  }
  if (!longest) return false;
  longest->evicted = true;
  boost::system::error_code ignored;
  longest->socket.close(ignored);
  return true;
}

/// Room for one more connection from `host` under both caps, made by closing the longest
/// waiting ones; false when there is none (then the new connection is closed). Counts either way.
bool make_room(State& state, const proto::HostKey& host) {
  int open = 0;
  int from_host = 0;
  for (const AdminConnection* connection : state.connections) {
    if (connection->evicted) continue;
    ++open;
    from_host += connection->host == host ? 1 : 0;
  }
  if (from_host >= state.options.max_connections_per_address) {
    state.reject(AdminRejectReason::TooManyFromAddress);
    if (!evict_longest_waiting(state, [&](const AdminConnection& c) { return c.host == host; })) {
      return false;
    }
    --open;
  }
  if (open >= state.options.max_connections) {
    state.reject(AdminRejectReason::TooManyConnections);
    return evict_longest_waiting(state, [](const AdminConnection&) { return true; });
  }
  return true;
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
    const proto::HostKey host = host_key_of(socket);
    if (!make_room(*state, host)) {
      boost::system::error_code ignored;
      socket.close(ignored);
      continue;
    }
    auto connection = std::make_shared<AdminConnection>(std::move(socket), host);
    connection->deadline = deadline_from_now(*state);
    connection->waiting_since = ++state->waits;
    // Counted from here, so the next accept's caps see it before it is served.
    state->connections.insert(connection.get());
    state->open = state->connections.size();
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
