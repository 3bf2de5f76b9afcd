#pragma once
/// The admin HTTP port (Boost.Beast, coroutines): GET /metrics (Prometheus text 0.0.4),
/// GET /healthz (200 while the health callback says the matches tick on time, else 503),
/// GET /readyz (200 once the ready callback says sockets are bound and the DB is open, else 503).
/// POST /accounts/<name>/ban and POST /accounts/<name>/unban (an operator's action, answered
/// once the account callback has done it: 200, 404 for an unknown name, 503 when the database
/// cannot take it now).
/// GET /fleet (application/json, fleet_view.h): every live row of the fleet directory with its
/// matches, this server's marked "self", read through the DB worker: 503 when the database
/// cannot answer now; 404 when the server keeps no directory row ([placement] off).
/// Other paths: 404; other methods on these paths: 405. HTTP/1.1 keep-alive.
///
/// Requests are untrusted: a request must arrive whole within request_timeout of the server
/// starting to wait for it (slow senders and idle keep-alive connections are closed; a
/// response must be written within it too), headers and body are bounded by max_request_bytes
/// (431 or 413, then closed), unparsable requests get 400 and are closed. Each is counted by
/// reason in ricochet_admin_rejected_total{reason}.
///
/// Exposed (issue 29): at most max_connections open, and max_connections_per_address from one
/// address (proto::HostKey) besides its event streams, of which it may hold
/// max_streams_per_address (one more is answered 503). A connection beyond either cap closes
/// the one of them that has
/// waited longest for a request (an idle keep-alive, a slow sender), so whoever holds
/// connections open without using them cannot keep a /healthz probe out; only when every one is
/// busy writing a response is the newcomer closed. With a bearer token, /metrics answers 401
/// without "Authorization: Bearer <token>" (compared in constant time; each address's refusals
/// logged once per episode), and so does /fleet; /healthz and /readyz stay open to probes. The
/// account actions need the token too, and without one they are allowed only when the port is bound
/// to a loopback address (403 otherwise: whoever reaches an exposed port could ban anyone).
///
/// Everything runs on a strand of the given io_context; the callbacks are called there and must
/// be thread-safe towards the code that owns what they read. Deadlines are on options.clock; a
/// timer per connection wakes at its deadline, or check_deadlines() makes them look now.
///
/// The dashboard (issue 32): the files of options.files (embedded at build time:
/// dashboard_files.h) by GET, "/" being /index.html, with their Content-Type, a strong ETag
/// (If-None-Match: 304) and Cache-Control: no-cache; and the routes added by add_route() before
/// start(), each an exact path or a prefix, answered with JSON or held open as a stream. Every
/// response carries Content-Security-Policy (default-src 'self', frame-ancestors 'none'),
/// X-Content-Type-Options: nosniff and Referrer-Policy: no-referrer.
///
/// With a token, the files (but options.public_files: the sign-in page and its style), the
/// routes and /metrics need it: "Authorization: Bearer <token>" from scripts, or from a browser,
/// which cannot add a header to a navigation, a session cookie. POST /signin with the form field
/// token=<token> (compared in constant time) makes a session: 32 random bytes, known to the
/// server only by their value in its table (at most max_sessions, the oldest replaced; each
/// lasts session_lifetime on options.clock), sent back in an HttpOnly, SameSite=Strict cookie;
/// POST /signout ends it. An address that sent max_signin_failures wrong tokens within
/// signin_window is answered 429 with Retry-After until its window ends, the right token too
/// (counted as sign_in_limited, logged once per episode per address). A page asked for without
/// either is sent to /signin (303), anything else is 401; both are counted and logged once per
/// episode per address, as /metrics' are.
/// The account actions take the bearer token only (no cookie: a form elsewhere cannot ban).
///
/// Live data goes as server-sent events (text/event-stream) over the connection that asked for
/// it, not a WebSocket: the browser's EventSource reconnects by itself, passes the session
/// cookie like any request, needs no upgrade handshake, frames or masking here, and the data
/// flows one way only (server to page). Each stream is an AdminEventStream: a producer on any
/// thread pushes messages into a queue of at most max_stream_queue; a browser that falls that
/// far behind is dropped (slow_reader), so a producer never waits for one. Each write must end
/// within request_timeout, as a response's.

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/system/error_code.hpp>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "dashboard_files.h"
#include "episode_log.h"
#include "ricochet/proto/clock.h"
#include "ricochet/server/metrics.h"
#include "steady_time.h"

namespace ricochet::server {

struct AdminHttpOptions {
  std::string bind = "127.0.0.1";                   ///< IP address literal
  std::uint16_t port = 9100;                        ///< 0: any free port (see local_endpoint())
  std::size_t max_request_bytes = 8192;             ///< request line and headers; body likewise
  std::chrono::milliseconds request_timeout{5000};  ///< from the first byte awaited to the last
  int max_connections = 32;                         ///< open at once
  /// Open at once from one proto::HostKey, its event streams not counted: a browser's pages,
  /// files and JSON, or a script's requests. A browser opens up to 6 connections to a host when
  /// a page fetches in parallel (the Recordings page reads frames ahead): at 4, its fifth closed
  /// an idle keep-alive one the browser was about to reuse, and that request failed. 8 holds a
  /// browser's 6 and a script's 2.
  int max_connections_per_address = 8;
  /// Event streams open at once from one proto::HostKey, beside those. Each dashboard tab holds
  /// one stream (the overview's events or a live match) for as long as it is open, never idle, so
  /// never closed to make room: counted among the connections above, a few tabs' streams left the
  /// pages' requests none (each further connection closed at once). One more stream is refused
  /// (503), and whatever one address opens holds at most 12 of max_connections, so it cannot keep
  /// another out.
  int max_streams_per_address = 4;
  /// What /metrics requires in "Authorization: Bearer <token>"; empty: nothing.
  std::string bearer_token;
  /// Logs refused tokens once per episode; nullptr: they are only counted.
  EpisodeLog* episodes = nullptr;
  /// The files served by GET at their path; "/" is /index.html.
  std::span<const EmbeddedFile> files;
  /// Those of files served without the token: what the sign-in page needs.
  std::vector<std::string> public_files = {"/signin.html", "/style.css", "/favicon.svg"};
  int max_sessions = 32;                           ///< browser sessions held at once
  std::chrono::minutes session_lifetime{12 * 60};  ///< from the sign-in
  std::size_t max_stream_queue = 16;               ///< messages a stream holds for a slow reader
  /// Wrong tokens at POST /signin from one address per signin_window; beyond: 429 until the
  /// window (opened by the address's first wrong token) ends (admin_signin_limiter.h).
  int max_signin_failures = 10;
  std::chrono::seconds signin_window{60};
  std::size_t max_signin_addresses = 1024;  ///< addresses whose wrong tokens are remembered
  /// What the deadlines are measured on, in µs; tests pass fake time and call check_deadlines().
  std::function<proto::TimeUs()> clock = steady_now_us;
};

/// Why a request or connection was refused.
enum class AdminRejectReason {
  Malformed,           ///< not parsable as HTTP/1.x: 400, closed
  Oversized,           ///< headers or body above max_request_bytes: 431 or 413, closed
  Timeout,             ///< not complete within request_timeout: closed without a reply
  NotFound,            ///< unknown path: 404
  MethodNotAllowed,    ///< not GET: 405
  TooManyConnections,  ///< above max_connections: the longest waiting (or the new one) closed
  TooManyFromAddress,  ///< above max_connections_per_address: likewise, among that address's
  Unauthorized,        ///< /metrics, /fleet or an account action without the token: 401
  Forbidden,           ///< an account action, no token configured, bound beyond loopback: 403
  SlowReader,          ///< an event stream's reader max_stream_queue messages behind: closed
  SignInLimited,       ///< POST /signin from an address out of wrong tokens: 429
  TooManyStreams,      ///< an event stream above max_streams_per_address: 503
};
inline constexpr std::size_t kAdminRejectReasonCount =
    static_cast<std::size_t>(AdminRejectReason::TooManyStreams) + 1;
/// "malformed", "oversized", "timeout", "not_found", "method_not_allowed", "too_many_connections",
/// "too_many_from_address", "unauthorized", "forbidden", "slow_reader", "sign_in_limited",
/// "too_many_streams".
const char* name(AdminRejectReason reason);

/// What an operator asks of an account.
struct AccountAction {
  std::string username;          ///< 1..64 of [A-Za-z0-9_.-], as in the path
  bool ban = true;               ///< false: unban
  std::string operator_address;  ///< who asked (proto::HostKey text), for the log
};

/// The answer to an AccountAction or a /fleet request: an HTTP status and its body.
struct AdminReply {
  unsigned status = 200;
  std::string body;  ///< a line for the operator, or /fleet's JSON
  std::string content_type = "text/plain; charset=utf-8";
};

struct AdminHttpCallbacks {
  std::function<bool()> healthy;  ///< true while every match ticks on time
  std::function<bool()> ready;    ///< true once sockets are bound and the DB is open
  /// Does an account action and calls `answer` once, from any thread; empty: /accounts is 404.
  std::function<void(AccountAction action, std::function<void(AdminReply)> answer)> account;
  /// Answers GET /fleet by calling `answer` once, from any thread; empty: /fleet is 404.
  std::function<void(std::function<void(AdminReply)> answer)> fleet;
};

/// A request as a route's handler sees it.
struct AdminRequest {
  std::string method;  ///< "GET", "POST" ...
  std::string path;    ///< the target less its query
  std::string query;   ///< after '?', undecoded; empty when none
  std::string body;
};

/// One open event stream (server-sent events), fed from any thread.
class AdminEventStream {
 public:
  explicit AdminEventStream(std::size_t max_queue) : max_queue_(max_queue) {}
  /// Queues one event whose data is `data` (one line: line breaks are sent as spaces). False
  /// when the stream is closed (the browser left, was too slow, or the server stops): the
  /// producer forgets it.
  bool push(std::string data);
  bool closed() const;

  // For AdminHttp's connection (any thread).
  /// The queued events, oldest first; empty when none.
  std::deque<std::string> take();
  /// Marks it closed (the browser left or the server stops).
  void close();
  /// Whether it was closed for holding max_queue events unsent.
  bool overflowed() const;
  /// Called once a message is pushed or the stream closes (AdminHttp wakes the writer).
  void on_wake(std::function<void()> wake);

 private:
  const std::size_t max_queue_;
  mutable std::mutex mutex_;
  std::deque<std::string> queue_;
  bool closed_ = false;
  bool overflowed_ = false;
  std::function<void()> wake_;
};

/// Answers a request once, from any thread (a route's JSON: content_type "application/json").
using AdminAnswer = std::function<void(AdminReply)>;

/// One entry of the route table: an exact path, or every path under a prefix ending in '/'.
struct AdminRoute {
  std::string path;  ///< "/api/overview", or "/api/replays/" with prefix
  bool prefix = false;
  std::string method = "GET";  ///< the one method it takes (405 for others)
  /// A JSON (or any) answer; called on AdminHttp's strand, once the token rule passed.
  std::function<void(const AdminRequest& request, AdminAnswer answer)> handler;
  /// Or, when set instead, an event stream: given the open stream on the strand once its
  /// header went out; the producer keeps it and pushes to it.
  std::function<void(const AdminRequest& request, std::shared_ptr<AdminEventStream> stream)> stream;
  /// With a stream, optionally: called on the strand first; a reply answers the request instead
  /// of the stream (a refusal such as 404 or 503, or a path under the prefix that is not a
  /// stream), nullopt opens the stream.
  std::function<std::optional<AdminReply>(const AdminRequest& request)> before_stream;
};

class AdminHttp {
 public:
  /// Registers its own counters as a collect callback in `metrics` (ricochet_admin_*), which
  /// must outlive every scrape (the io_context's run).
  AdminHttp(boost::asio::io_context& io, AdminHttpOptions options, MetricsRegistry& metrics,
            AdminHttpCallbacks callbacks);
  /// stop().
  ~AdminHttp();
  AdminHttp(const AdminHttp&) = delete;
  AdminHttp& operator=(const AdminHttp&) = delete;

  /// Adds a route; call before start(). Routes are matched after the built-in paths, exact
  /// paths before prefixes, the longest prefix first; one path may have a route per method.
  void add_route(AdminRoute route);

  /// Binds, listens and starts accepting on the io_context. Returns the bind or listen error
  /// (e.g. address in use); then nothing is accepted. Call once.
  boost::system::error_code start();
  /// The bound address; valid after a successful start() (the chosen port when port was 0).
  boost::asio::ip::tcp::endpoint local_endpoint() const { return endpoint_; }
  /// Closes the listener and every connection. Thread-safe; idempotent.
  void stop();
  /// Makes every connection compare its deadline with options.clock now rather than when its
  /// timer fires (for a clock that moves other than in real time). Thread-safe; returns at once.
  void check_deadlines();

  /// Connections open now (accepted, not yet closed).
  std::size_t connections() const;
  /// Requests answered (any status) and refusals by reason so far. A keep-alive connection's
  /// next request is awaited (its deadline runs) from before its response is counted.
  std::uint64_t responses() const;
  std::uint64_t rejected(AdminRejectReason reason) const;

  struct State;

 private:
  std::shared_ptr<State> state_;
  boost::asio::ip::tcp::endpoint endpoint_;
};

}  // namespace ricochet::server
