#pragma once
/// The bot's control channel: the I/O layer (TCP, TLS 1.3, the server's certificate checked by
/// fingerprint with ServerTrust) under proto::ControlClient, which numbers the requests, matches
/// the replies, follows the connection's state, times requests out and keeps the connection
/// alive. Callback-driven, no blocking call: many clients share one io_context, and every
/// callback runs on it.

#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/asio/steady_timer.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "ricochet/bot/server_trust.h"
#include "ricochet/proto/control_client.h"

namespace ricochet::bot {

/// A TLS client context as the control channel needs it: TLS 1.3 only, no chain validation
/// (the certificate is pinned by fingerprint instead). One per process is enough.
boost::asio::ssl::context make_control_tls_context();

class ControlClient : public std::enable_shared_from_this<ControlClient> {
 public:
  struct Callbacks {
    /// TLS is up and the server trusted (error empty), or why not. Called once.
    std::function<void(const std::string& error)> on_ready;
    /// A match this account played ended (the connection is back in Authenticated).
    std::function<void(const wire::MatchResults& results)> on_match_results;
    /// The connection ended: the server closed it (with its reason when it gave one), a request
    /// had no reply in time, or the server sent something the protocol does not allow.
    std::function<void(const std::string& reason)> on_closed;
  };
  /// The request's reply body or its Error.
  using ReplyHandler = std::function<void(const wire::ServerMessage& reply)>;

  ControlClient(boost::asio::io_context& io, boost::asio::ssl::context& tls, ServerTrust& trust,
                Callbacks callbacks, proto::ControlClientConfig config = {});
  ControlClient(const ControlClient&) = delete;
  ControlClient& operator=(const ControlClient&) = delete;

  /// `local`: the address to connect from (any free port on it); unspecified: the system's.
  void connect(const boost::asio::ip::tcp::endpoint& server,
               const boost::asio::ip::address& local = {});
  /// Sends `message` (written once TLS is up) and calls `on_reply` with the server's answer.
  /// False, with nothing sent, when the connection's state does not allow the request
  /// (control_states.h) or the connection is closed.
  bool request(wire::ClientMessage message, ReplyHandler on_reply);
  /// Ends the connection at once; no callback is called after this.
  void close();

  bool is_open() const { return ready_ && !closed_; }
  proto::ControlState state() const { return protocol_.state(); }
  /// The handshake completed but the server's certificate was not trusted (a fatal refusal:
  /// retrying cannot help).
  bool untrusted() const { return untrusted_; }
  /// The connection was closed because the server sent something the protocol does not allow
  /// (a bad frame, a reply that answers nothing); proto::ControlClient's counters say what.
  bool refused_server() const;

 private:
  void on_connected(const boost::system::error_code& error);
  void on_handshake(const boost::system::error_code& error);
  void read_more();
  void on_read(const boost::system::error_code& error, std::size_t bytes);
  /// After any input: hands the events to their handlers, writes what is queued, re-arms the
  /// protocol's deadline.
  void pump();
  void write_next();
  void arm_deadline();
  void fail(const std::string& reason);

  boost::asio::ssl::stream<boost::asio::ip::tcp::socket> stream_;
  ServerTrust& trust_;
  Callbacks callbacks_;
  proto::ControlClient protocol_;
  std::unordered_map<std::uint32_t, ReplyHandler> handlers_;  ///< by request id
  std::array<std::uint8_t, 16384> read_buffer_{};
  std::vector<std::uint8_t> writing_;   ///< the bytes being written
  boost::asio::steady_timer deadline_;  ///< protocol_.deadline(), when it has one
  std::optional<proto::TimeUs> armed_for_;
  bool ready_ = false;
  bool closed_ = false;
  bool untrusted_ = false;
};

}  // namespace ricochet::bot
