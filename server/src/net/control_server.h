#pragma once
/// The control channel's listener (TCP, TLS 1.3 only): accepts connections under the caps on
/// connections in total and per address, and runs a ControlSession for each. Everything runs on
/// one strand of the io_context the server is given, so the io_context may run on any number of
/// threads; the public calls below are thread-safe unless they say otherwise.
///
///   asio::io_context io;
///   db::DbWorker db(...);
///   ControlServer control(io, config, db, directory);  // loads or makes the TLS pair
///   spdlog::info("control on port {}, fingerprint {}", ...,
///   control.identity().fingerprint_sha256); control.start();                                    //
///   binds; throws if it cannot
///   ... io.run() on the worker threads ...
///   control.stop();     // on SIGTERM: closes the listener, tells every client SHUTTING_DOWN
///   // the sessions end within 2 s; io.run() returns when nothing else is left
///
/// Lifetime: the db worker and the directory outlive the server; destroy the server only once
/// its io_context has stopped running (after run() returned, or io.stop()), and stop the
/// DbWorker before the io_context is destroyed.

#include <atomic>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl/context.hpp>
#include <boost/asio/strand.hpp>
#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>

#include "control_config.h"
#include "control_counters.h"
#include "control_session.h"
#include "match_directory.h"
#include "ricochet/db/db_worker.h"
#include "tls_identity.h"

namespace ricochet::server {

class ControlServer {
 public:
  /// Validates the config (std::invalid_argument naming the field) and loads or generates the
  /// TLS identity (TlsIdentityError). Binds nothing yet.
  ControlServer(boost::asio::io_context& io, ControlServerConfig config, db::DbWorker& db,
                MatchDirectory& matches);
  ~ControlServer();
  ControlServer(const ControlServer&) = delete;
  ControlServer& operator=(const ControlServer&) = delete;

  /// Binds bind_address:port and starts accepting. Throws boost::system::system_error when the
  /// address cannot be bound. Call once, before or while the io_context runs.
  void start();
  /// Stops accepting and closes every session with an Error SHUTTING_DOWN. Returns at once.
  void stop();
  /// Makes every session compare its deadlines with the config's clock now. The sessions' own
  /// timers do so at each deadline in real time; a test that moves a fake clock calls this.
  /// Returns at once.
  void check_deadlines();

  /// The bound port (the chosen one when the config asked for 0); 0 before start().
  std::uint16_t port() const { return port_.load(); }
  const TlsIdentity& identity() const { return identity_; }
  /// Open sessions (handshaking, connected or closing).
  std::size_t connections() const { return connections_.load(); }
  ControlStats stats() const { return counters_.snapshot(); }
  const ControlCounters& counters() const { return counters_; }

  /// Queues `message` (request_id 0) to every session logged in as `account`; a MatchResults
  /// body also moves those sessions from InMatch back to Authenticated.
  void send_to_account(std::uint64_t account, wire::ServerMessage message);
  /// A ban: closes every session logged in as `account` with an Error ACCOUNT_BANNED
  /// (request_id 0, `message`), and from now on refuses its logins and resumes that complete
  /// here (one the database let through just before the ban). Then runs `then` on the strand
  /// with how many sessions it closed (nothing can sign the account in between).
  void ban_account(std::uint64_t account, std::string message,
                   std::function<void(std::size_t closed)> then);
  /// Undoes ban_account's refusal of the account's logins (the database's ban is the caller's).
  void unban_account(std::uint64_t account);

 private:
  boost::asio::awaitable<void> accept_loop();
  /// Admits an accepted socket under the caps, or closes it; returns whether it was admitted.
  bool admit(boost::asio::ip::tcp::socket& socket, const std::string& address);
  void ended(ControlSession& session);

  ControlServerConfig config_;
  TlsIdentity identity_;
  boost::asio::ssl::context tls_;
  boost::asio::strand<boost::asio::io_context::executor_type> strand_;
  boost::asio::ip::tcp::acceptor acceptor_;
  ControlCounters counters_;
  ControlContext context_;
  std::unordered_map<std::uint64_t, std::shared_ptr<ControlSession>> sessions_;
  std::unordered_map<std::string, int> per_address_;
  std::uint64_t next_session_id_ = 1;
  bool stopping_ = false;
  std::atomic<std::uint16_t> port_{0};
  std::atomic<std::size_t> connections_{0};
};

}  // namespace ricochet::server
