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
/// address (proto::HostKey). A connection beyond either cap closes the one of them that has
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

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/system/error_code.hpp>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

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
  int max_connections = 16;                         ///< open at once
  int max_connections_per_address = 4;              ///< open at once from one proto::HostKey
  /// What /metrics requires in "Authorization: Bearer <token>"; empty: nothing.
  std::string bearer_token;
  /// Logs refused tokens once per episode; nullptr: they are only counted.
  EpisodeLog* episodes = nullptr;
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
};
inline constexpr std::size_t kAdminRejectReasonCount =
    static_cast<std::size_t>(AdminRejectReason::Forbidden) + 1;
/// "malformed", "oversized", "timeout", "not_found", "method_not_allowed", "too_many_connections",
/// "too_many_from_address", "unauthorized", "forbidden".
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
