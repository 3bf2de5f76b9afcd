#include "admin_http.h"

#include <openssl/rand.h>
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
#include <boost/asio/write.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/http.hpp>
#include <chrono>
#include <exception>
#include <limits>
#include <optional>
#include <string_view>
#include <tuple>
#include <unordered_set>
#include <variant>

#include "admin_signin_limiter.h"
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
    case AdminRejectReason::SlowReader:
      return "slow_reader";
    case AdminRejectReason::SignInLimited:
      return "sign_in_limited";
    case AdminRejectReason::TooManyStreams:
      return "too_many_streams";
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
  std::shared_ptr<AdminEventStream> stream;  ///< once it streams events
};

/// A browser's sign-in, known by its random id (64 hex digits) until it expires.
struct AdminSession {
  std::string id;
  proto::TimeUs expires = 0;  ///< on options.clock
};

struct AdminHttp::State {
  State(asio::io_context& io, AdminHttpOptions options_in, MetricsRegistry& metrics_in,
        AdminHttpCallbacks callbacks_in)
      : strand(asio::make_strand(io)),
        acceptor(strand),
        options(std::move(options_in)),
        metrics(metrics_in),
        callbacks(std::move(callbacks_in)),
        sign_ins(
            options.max_signin_failures,
            std::chrono::duration_cast<std::chrono::microseconds>(options.signin_window).count(),
            options.max_signin_addresses) {}

  void reject(AdminRejectReason reason) {
    rejected[static_cast<int>(reason)].fetch_add(1, std::memory_order_relaxed);
  }

  asio::strand<asio::io_context::executor_type> strand;
  tcp::acceptor acceptor;  ///< used on the strand only
  const AdminHttpOptions options;
  MetricsRegistry& metrics;
  const AdminHttpCallbacks callbacks;
  std::unordered_set<AdminConnection*> connections;  ///< open ones; on the strand only
  std::vector<AdminRoute> routes;                    ///< add_route(), before start()
  std::vector<AdminSession> sessions;                ///< on the strand only
  AdminSignInLimiter sign_ins;       ///< wrong tokens by address; on the strand only
  bool stopped = false;              ///< on the strand only
  std::uint64_t waits = 0;           ///< waits for a request begun so far; on the strand only
  std::atomic<std::size_t> open{0};  ///< connections.size(), for any thread
  std::atomic<std::uint64_t> responses{0};
  std::array<std::atomic<std::uint64_t>, kAdminRejectReasonCount> rejected{};
};

namespace {

using Request = http::request<http::string_body>;
using Response = http::response<http::string_body>;
using State = AdminHttp::State;

/// The deadline of a connection waiting for events to send: none (each write has its own).
constexpr proto::TimeUs kNoDeadline = std::numeric_limits<proto::TimeUs>::max();
/// The cookie a browser's session travels in.
constexpr std::string_view kSessionCookie = "ricochet_session";
/// Every response's: only this server's own scripts, styles, images and connections; never in
/// a frame; forms post here only.
constexpr std::string_view kContentSecurityPolicy =
    "default-src 'self'; base-uri 'none'; form-action 'self'; frame-ancestors 'none'";

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

std::string_view field_of(const Request& request, http::field name) {
  const auto header = request.find(name);
  if (header == request.end()) return {};
  return {header->value().data(), header->value().size()};
}

/// The value of the cookie `name` in the request's Cookie header; empty when it has none.
std::string_view cookie_of(const Request& request, std::string_view name) {
  std::string_view rest = field_of(request, http::field::cookie);
  while (!rest.empty()) {
    const auto end = rest.find(';');
    std::string_view pair = rest.substr(0, end);
    while (!pair.empty() && pair.front() == ' ') pair.remove_prefix(1);
    const auto equals = pair.find('=');
    if (equals != std::string_view::npos && pair.substr(0, equals) == name) {
      return pair.substr(equals + 1);
    }
    if (end == std::string_view::npos) break;
    rest.remove_prefix(end + 1);
  }
  return {};
}

/// Whether `id` is a session not expired; every session is compared, in constant time each.
bool known_session(const State& state, std::string_view id) {
  if (id.empty()) return false;
  const proto::TimeUs now = state.options.clock();
  bool known = false;
  for (const AdminSession& session : state.sessions) {
    known = (same_secret(id, session.id) && session.expires > now) || known;
  }
  return known;
}

/// With a token configured: "Authorization: Bearer <token>", or (`cookie_ok`) a session cookie.
bool authorized(const State& state, const Request& request, bool cookie_ok = false) {
  const std::string& token = state.options.bearer_token;
  if (token.empty()) return true;
  if (cookie_ok && known_session(state, cookie_of(request, kSessionCookie))) return true;
  const std::string_view value = field_of(request, http::field::authorization);
  constexpr std::string_view kScheme = "Bearer ";
  if (value.size() < kScheme.size() || value.substr(0, kScheme.size()) != kScheme) return false;
  return same_secret(value.substr(kScheme.size()), token);
}

/// The headers every response carries.
void secure(Response& response) {
  response.set("Content-Security-Policy", kContentSecurityPolicy);
  response.set("X-Content-Type-Options", "nosniff");
  response.set("Referrer-Policy", "no-referrer");
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

/// Counts a request without the token, and logs it once per episode per address.
void refuse_unauthorized(State& state, const AdminConnection& connection, std::string_view what) {
  state.reject(AdminRejectReason::Unauthorized);
  const std::string detail = std::string(what) + " without the admin bearer token";
  if (state.options.episodes) {
    state.options.episodes->refuse(name(AdminRejectReason::Unauthorized),
                                   connection.host.to_string(), detail, state.options.clock());
  }
}

/// The 401 of a request without the bearer token, logged once per episode per address.
Response unauthorized(State& state, const AdminConnection& connection, unsigned version,
                      std::string_view what) {
  refuse_unauthorized(state, connection, what);
  Response response = text_response(http::status::unauthorized, version,
                                    std::string(what) + " needs Authorization: Bearer <token>\n");
  response.set(http::field::www_authenticate, "Bearer");
  return response;
}

/// GET /fleet, authorized: the fleet callback answers it.
struct FleetRequest {};

/// A request for a route of the table: its handler is called, the answer awaited.
struct RouteCall {
  const AdminRoute* route = nullptr;
  AdminRequest request;
};

/// What a request gets: a response now, or an account action, the fleet or a route's handler
/// to ask first.
using Routed = std::variant<Response, AccountAction, FleetRequest, RouteCall>;

Response redirect(unsigned version, std::string_view location) {
  Response response =
      text_response(http::status::see_other, version, "see " + std::string(location) + "\n");
  response.set(http::field::location, location);
  return response;
}

Response method_not_allowed(State& state, unsigned version, std::string_view allowed) {
  state.reject(AdminRejectReason::MethodNotAllowed);
  Response response = text_response(http::status::method_not_allowed, version,
                                    "only " + std::string(allowed) + " is allowed here\n");
  response.set(http::field::allow, allowed);
  return response;
}

/// The form field `name` of an application/x-www-form-urlencoded body, decoded; nullopt when
/// it is missing or badly encoded.
std::optional<std::string> form_field(std::string_view body, std::string_view name) {
  while (!body.empty()) {
    const auto end = body.find('&');
    const std::string_view pair = body.substr(0, end);
    const auto equals = pair.find('=');
    if (equals != std::string_view::npos && pair.substr(0, equals) == name) {
      std::string value;
      const std::string_view encoded = pair.substr(equals + 1);
      for (std::size_t i = 0; i < encoded.size(); ++i) {
        if (encoded[i] == '+') {
          value += ' ';
        } else if (encoded[i] != '%') {
          value += encoded[i];
        } else {
          unsigned byte = 0;
          if (i + 2 >= encoded.size()) return std::nullopt;
          for (const char digit : encoded.substr(i + 1, 2)) {
            const auto at = std::string_view{"0123456789abcdef"}.find(
                static_cast<char>(digit >= 'A' && digit <= 'F' ? digit - 'A' + 'a' : digit));
            if (at == std::string_view::npos) return std::nullopt;
            byte = byte * 16 + static_cast<unsigned>(at);
          }
          value += static_cast<char>(byte);
          i += 2;
        }
      }
      return value;
    }
    if (end == std::string_view::npos) break;
    body.remove_prefix(end + 1);
  }
  return std::nullopt;
}

/// A new session's id (64 hex digits), held in state.sessions: expired ones are forgotten,
/// and the one to expire soonest when max_sessions are held. Empty when no random bytes came.
std::string open_session(State& state) {
  std::array<unsigned char, 32> bytes{};
  if (RAND_bytes(bytes.data(), static_cast<int>(bytes.size())) != 1) return {};
  std::string id;
  for (const unsigned char byte : bytes) {
    id += "0123456789abcdef"[byte >> 4];
    id += "0123456789abcdef"[byte & 15];
  }
  const proto::TimeUs now = state.options.clock();
  std::erase_if(state.sessions,
                [now](const AdminSession& session) { return session.expires <= now; });
  if (!state.sessions.empty() &&
      static_cast<int>(state.sessions.size()) >= state.options.max_sessions) {
    state.sessions.erase(std::min_element(
        state.sessions.begin(), state.sessions.end(),
        [](const AdminSession& a, const AdminSession& b) { return a.expires < b.expires; }));
  }
  const auto lifetime =
      std::chrono::duration_cast<std::chrono::microseconds>(state.options.session_lifetime);
  state.sessions.push_back({id, now + lifetime.count()});
  return id;
}

/// The 429 of a sign-in from an address out of wrong tokens for `wait_us` more, logged once
/// per episode per address.
Response sign_in_limited(State& state, const AdminConnection& connection, unsigned version,
                         proto::TimeUs now, proto::TimeUs wait_us) {
  state.reject(AdminRejectReason::SignInLimited);
  const auto& options = state.options;
  if (options.episodes) {
    options.episodes->refuse(name(AdminRejectReason::SignInLimited), connection.host.to_string(),
                             std::to_string(options.max_signin_failures) +
                                 " wrong admin tokens at POST /signin within " +
                                 std::to_string(options.signin_window.count()) + " s",
                             now);
  }
  const std::string seconds =
      std::to_string((wait_us + proto::kMicrosPerSecond - 1) / proto::kMicrosPerSecond);
  Response response = text_response(
      http::status::too_many_requests, version,
      "<!doctype html><html lang=\"en\"><meta charset=\"utf-8\"><title>Ricochet: too many "
      "tries</title><p>Too many wrong tokens from your address. Try again in " +
          seconds + " s. <a href=\"/signin\">Sign in</a></p>\n",
      "text/html; charset=utf-8");
  response.set(http::field::retry_after, seconds);
  return response;
}

/// POST /signin: the token in the form field "token" opens a session for this browser.
Response sign_in(State& state, const AdminConnection& connection, const Request& request) {
  const unsigned version = request.version();
  if (state.options.bearer_token.empty()) return redirect(version, "/");
  const proto::TimeUs now = state.options.clock();
  // A limited address's token is not compared, the right one neither: an answer that told the
  // right token apart would let a guesser go on guessing at full speed, reading the verdicts.
  if (const proto::TimeUs wait_us = state.sign_ins.wait_us(connection.host, now); wait_us > 0) {
    return sign_in_limited(state, connection, version, now, wait_us);
  }
  const std::optional<std::string> token = form_field(request.body(), "token");
  if (!token || !same_secret(*token, state.options.bearer_token)) {
    state.sign_ins.fail(connection.host, now);
    refuse_unauthorized(state, connection, "a sign-in");
    Response response = text_response(
        http::status::unauthorized, version,
        "<!doctype html><html lang=\"en\"><meta charset=\"utf-8\"><title>Ricochet: not signed "
        "in</title><p>That is not the admin token. <a href=\"/signin\">Try again</a></p>\n",
        "text/html; charset=utf-8");
    return response;
  }
  const std::string id = open_session(state);
  if (id.empty()) {
    return text_response(http::status::service_unavailable, version, "no random bytes\n");
  }
  Response response = redirect(version, "/");
  const auto max_age =
      std::chrono::duration_cast<std::chrono::seconds>(state.options.session_lifetime);
  response.set(http::field::set_cookie, std::string(kSessionCookie) + "=" + id +
                                            "; Path=/; HttpOnly; SameSite=Strict; Max-Age=" +
                                            std::to_string(max_age.count()));
  return response;
}

/// POST /signout: forgets this browser's session.
Response sign_out(State& state, const Request& request) {
  const std::string_view id = cookie_of(request, kSessionCookie);
  std::erase_if(state.sessions,
                [id](const AdminSession& session) { return same_secret(id, session.id); });
  Response response = redirect(request.version(), "/signin");
  response.set(http::field::set_cookie,
               std::string(kSessionCookie) + "=; Path=/; HttpOnly; SameSite=Strict; Max-Age=0");
  return response;
}

const EmbeddedFile* file_at(const State& state, std::string_view path) {
  if (path == "/") path = "/index.html";
  if (path == "/signin") path = "/signin.html";
  for (const EmbeddedFile& file : state.options.files) {
    if (file.path == path) return &file;
  }
  return nullptr;
}

/// GET of an embedded file: 304 when the browser holds this version.
Response serve_file(State& state, const AdminConnection& connection, const Request& request,
                    const EmbeddedFile& file) {
  const unsigned version = request.version();
  if (request.method() != http::verb::get) return method_not_allowed(state, version, "GET");
  const auto& open = state.options.public_files;
  if (std::find(open.begin(), open.end(), file.path) == open.end() &&
      !authorized(state, request, true)) {
    // A page is sent to the sign-in form; what a page loads is refused.
    if (file.content_type.starts_with("text/html")) {
      refuse_unauthorized(state, connection, file.path);
      return redirect(version, "/signin");
    }
    return unauthorized(state, connection, version, file.path);
  }
  const bool fresh = field_of(request, http::field::if_none_match) == file.etag;
  Response response =
      text_response(fresh ? http::status::not_modified : http::status::ok, version,
                    fresh ? std::string{} : std::string(file.bytes), file.content_type);
  response.set(http::field::etag, file.etag);
  response.set(http::field::cache_control, "no-cache");
  return response;
}

/// The route of the table for `path`: an exact one, else the longest prefix; of two routes of
/// one path, the one taking `method` (else either: 405).
const AdminRoute* route_at(const State& state, std::string_view path, std::string_view method) {
  const AdminRoute* found = nullptr;
  const auto better = [&found, method](const AdminRoute& route) {
    if (!found) return true;
    if (route.prefix != found->prefix) return !route.prefix;
    if (route.path.size() != found->path.size()) return route.path.size() > found->path.size();
    return route.method == method && found->method != method;
  };
  for (const AdminRoute& route : state.routes) {
    const bool matches = route.prefix ? path.starts_with(route.path) : route.path == path;
    if (matches && better(route)) found = &route;
  }
  return found;
}

/// The dashboard's paths: sign-in and -out, the files, the route table; nullopt: none of them.
std::optional<Routed> route_dashboard(State& state, const AdminConnection& connection,
                                      const Request& request, std::string_view path) {
  const unsigned version = request.version();
  if (path == "/signin" && request.method() == http::verb::post) {
    return sign_in(state, connection, request);
  }
  if (path == "/signin" && state.options.bearer_token.empty()) return redirect(version, "/");
  if (path == "/signout") {
    if (request.method() != http::verb::post) return method_not_allowed(state, version, "POST");
    return sign_out(state, request);
  }
  if (const EmbeddedFile* file = file_at(state, path)) {
    return serve_file(state, connection, request, *file);
  }
  const AdminRoute* route = route_at(state, path, request.method_string());
  if (!route) return std::nullopt;
  if (request.method_string() != route->method) {
    return method_not_allowed(state, version, route->method);
  }
  if (!authorized(state, request, true)) return unauthorized(state, connection, version, path);
  const std::string_view target{request.target().data(), request.target().size()};
  const auto query = target.find('?');
  return RouteCall{
      route,
      {std::string(request.method_string()), std::string(path),
       query == std::string_view::npos ? std::string{} : std::string(target.substr(query + 1)),
       request.body()}};
}

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
  if (auto routed = route_dashboard(state, connection, request, path)) return std::move(*routed);
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
    if (!authorized(state, request, true)) {
      return unauthorized(state, connection, version, "/metrics");
    }
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
    if (!authorized(state, request, true)) {
      return unauthorized(state, connection, version, "/fleet");
    }
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

proto::TimeUs deadline_from_now(const State& state) {
  return state.options.clock() +
         std::chrono::duration_cast<std::chrono::microseconds>(state.options.request_timeout)
             .count();
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

/// Sends `route`'s events on the connection until the stream or the connection closes: the
/// header, then each event as it is pushed, each write within request_timeout.
asio::awaitable<void> stream_events(std::shared_ptr<State> state,
                                    std::shared_ptr<AdminConnection> connection, RouteCall call) {
  constexpr auto token = asio::as_tuple(asio::use_awaitable);
  auto stream = std::make_shared<AdminEventStream>(state->options.max_stream_queue);
  auto wake = std::make_shared<asio::steady_timer>(state->strand);
  stream->on_wake([weak = std::weak_ptr<State>(state), wake] {
    if (const auto alive = weak.lock()) asio::post(alive->strand, [wake] { wake->cancel(); });
  });
  connection->stream = stream;
  std::string bytes =
      "HTTP/1.1 200 OK\r\nServer: ricochet-server\r\n"
      "Content-Type: text/event-stream\r\nCache-Control: no-store\r\n"
      "Content-Security-Policy: " +
      std::string(kContentSecurityPolicy) +
      "\r\nX-Content-Type-Options: nosniff\r\nReferrer-Policy: no-referrer\r\n"
      "Connection: close\r\n\r\n";
  connection->deadline = deadline_from_now(*state);
  boost::system::error_code error;
  std::size_t written = 0;
  std::tie(error, written) =
      co_await asio::async_write(connection->socket, asio::buffer(bytes), token);
  state->responses.fetch_add(1, std::memory_order_release);
  // A browser sends nothing more on a stream, so a read that completes means the tab closed (end
  // of file) or a client broke the protocol: either way the stream ends now rather than at its
  // next failed write, which for the overview is a second away and leaves the address's stream
  // counted, so a reloaded tab at max_streams_per_address would get a 503 it never retries.
  asio::co_spawn(
      state->strand,
      [connection, stream]() -> asio::awaitable<void> {
        std::array<char, 64> ignored{};
        co_await connection->socket.async_read_some(asio::buffer(ignored),
                                                    asio::as_tuple(asio::use_awaitable));
        stream->close();  // wakes the writer below
      },
      asio::detached);
  if (!error && !state->stopped) call.route->stream(call.request, stream);
  while (!error && !state->stopped) {
    std::deque<std::string> events = stream->take();
    if (events.empty()) {
      if (stream->closed()) break;
      connection->deadline = kNoDeadline;
      wake->expires_at(asio::steady_timer::time_point::max());
      co_await wake->async_wait(token);
      continue;
    }
    bytes.clear();
    for (std::string& event : events) {
      std::replace(event.begin(), event.end(), '\n', ' ');
      std::replace(event.begin(), event.end(), '\r', ' ');
      bytes += "data: " + event + "\n\n";
    }
    connection->deadline = deadline_from_now(*state);
    std::tie(error, written) =
        co_await asio::async_write(connection->socket, asio::buffer(bytes), token);
  }
  stream->close();
  if (stream->overflowed()) {
    state->reject(AdminRejectReason::SlowReader);
    spdlog::warn("admin http: {} fell {} events behind on {}: closed", connection->host.to_string(),
                 state->options.max_stream_queue, call.request.path);
  }
}

/// Event streams open from `host`.
int streams_from(const State& state, const proto::HostKey& host) {
  return static_cast<int>(std::count_if(
      state.connections.begin(), state.connections.end(),
      [&host](const AdminConnection* c) { return c->stream && !c->evicted && c->host == host; }));
}

/// The 503 of a stream above max_streams_per_address.
Response too_many_streams(State& state, unsigned version) {
  state.reject(AdminRejectReason::TooManyStreams);
  return text_response(http::status::service_unavailable, version,
                       "at most " + std::to_string(state.options.max_streams_per_address) +
                           " live pages from one address at once; close one\n");
}

/// Closes the connection's socket once options.clock reaches its deadline (the pending read or
/// write then ends with an error). The deadline may move on while it waits.
asio::awaitable<void> watch(std::shared_ptr<State> state,
                            std::shared_ptr<AdminConnection> connection) {
  constexpr auto token = asio::as_tuple(asio::use_awaitable);
  while (!connection->served) {
    if (connection->deadline == kNoDeadline) {
      connection->watchdog.expires_at(asio::steady_timer::time_point::max());
      co_await connection->watchdog.async_wait(token);
      continue;
    }
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
      std::optional<AdminReply> instead;
      if (auto* call = std::get_if<RouteCall>(&routed);
          call && call->route->stream && call->route->before_stream) {
        instead = call->route->before_stream(call->request);
      }
      if (instead) {
        routed = text_response(static_cast<http::status>(instead->status), request.version(),
                               std::move(instead->body), instead->content_type);
      }
      if (auto* call = std::get_if<RouteCall>(&routed); call && call->route->stream) {
        if (streams_from(*state, connection->host) < options.max_streams_per_address) {
          co_await stream_events(state, connection, std::move(*call));
          break;
        }
        routed = too_many_streams(*state, request.version());
      }
      if (auto* call = std::get_if<RouteCall>(&routed)) {
        connection->deadline = deadline_from_now(*state);
        AdminReply reply = co_await await_reply(
            state, [&call](AdminAnswer answer) { call->route->handler(call->request, answer); });
        routed = text_response(static_cast<http::status>(reply.status), request.version(),
                               std::move(reply.body), reply.content_type);
      }
      response = std::move(std::get<Response>(routed));
      keep_alive = request.keep_alive();
      response.keep_alive(keep_alive);
    }
    secure(response);
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
    from_host += connection->host == host && !connection->stream ? 1 : 0;
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

void AdminHttp::add_route(AdminRoute route) {
  state_->routes.push_back(std::move(route));
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
    for (AdminConnection* connection : state->connections) {
      connection->socket.close(ignored);
      if (connection->stream) connection->stream->close();
    }
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

bool AdminEventStream::push(std::string data) {
  std::function<void()> wake;
  {
    const std::lock_guard lock(mutex_);
    if (closed_) return false;
    if (queue_.size() >= max_queue_) {
      closed_ = true;
      overflowed_ = true;
      queue_.clear();
    } else {
      queue_.push_back(std::move(data));
    }
    wake = wake_;
  }
  if (wake) wake();
  return !overflowed();
}

bool AdminEventStream::closed() const {
  const std::lock_guard lock(mutex_);
  return closed_;
}

std::deque<std::string> AdminEventStream::take() {
  const std::lock_guard lock(mutex_);
  return std::exchange(queue_, {});
}

void AdminEventStream::close() {
  std::function<void()> wake;
  {
    const std::lock_guard lock(mutex_);
    if (closed_) return;
    closed_ = true;
    wake = wake_;
  }
  if (wake) wake();
}

bool AdminEventStream::overflowed() const {
  const std::lock_guard lock(mutex_);
  return overflowed_;
}

void AdminEventStream::on_wake(std::function<void()> wake) {
  const std::lock_guard lock(mutex_);
  wake_ = std::move(wake);
}

}  // namespace ricochet::server
