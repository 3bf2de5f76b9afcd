#pragma once
/// The client end of the control channel (PROTOCOL.md Control channel) over Asio: TCP, TLS 1.3,
/// the server's certificate checked by fingerprint (ServerTrust), length-prefixed protobuf
/// frames. Requests are numbered from 1 and answered in order; messages the server sends on its
/// own (request_id 0: MatchResults, a closing Error) go to on_push. Callback-driven, no blocking
/// call: many clients share one io_context. Deadlines are the owner's (it calls close()).

#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl.hpp>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "ricochet/bot/server_trust.h"
#include "ricochet/proto/frame.h"
#include "ricochet/wire/control.pb.h"

namespace ricochet::bot {

/// A TLS client context as the control channel needs it: TLS 1.3 only, no chain validation
/// (the certificate is pinned by fingerprint instead). One per process is enough.
boost::asio::ssl::context make_control_tls_context();

class ControlClient : public std::enable_shared_from_this<ControlClient> {
 public:
  struct Callbacks {
    /// TLS is up and the server trusted (error empty), or why not. Called once.
    std::function<void(const std::string& error)> on_ready;
    /// A message with request_id 0.
    std::function<void(const wire::ServerMessage& message)> on_push;
    /// The connection ended (the server closed it, or it sent something that makes no sense).
    std::function<void(const std::string& reason)> on_closed;
  };
  using ReplyHandler = std::function<void(const wire::ServerMessage& reply)>;

  ControlClient(boost::asio::io_context& io, boost::asio::ssl::context& tls, ServerTrust& trust,
                Callbacks callbacks);
  ControlClient(const ControlClient&) = delete;
  ControlClient& operator=(const ControlClient&) = delete;

  /// `local`: the address to connect from (any free port on it); unspecified: the system's.
  void connect(const boost::asio::ip::tcp::endpoint& server,
               const boost::asio::ip::address& local = {});
  /// Numbers `message`, sends it, and calls `on_reply` with the server's answer.
  void request(wire::ClientMessage message, ReplyHandler on_reply);
  /// Ends the connection at once; no callback is called after this.
  void close();

  bool is_open() const { return ready_ && !closed_; }
  /// The handshake completed but the server's certificate was not trusted (a fatal refusal:
  /// retrying cannot help).
  bool untrusted() const { return untrusted_; }
  /// Frames the server sent that were refused (bad framing or not a ServerMessage), and replies
  /// that answered no request.
  std::uint64_t bad_frames() const { return bad_frames_; }

 private:
  void on_connected(const boost::system::error_code& error);
  void on_handshake(const boost::system::error_code& error);
  void read_more();
  void on_read(const boost::system::error_code& error, std::size_t bytes);
  void dispatch(const wire::ServerMessage& message);
  void write_next();
  void fail(const std::string& reason);

  boost::asio::ssl::stream<boost::asio::ip::tcp::socket> stream_;
  ServerTrust& trust_;
  Callbacks callbacks_;
  proto::FrameReader reader_;
  std::array<std::uint8_t, 16384> read_buffer_{};
  std::vector<std::uint8_t> payload_;
  std::deque<std::vector<std::uint8_t>> outbox_;  ///< frames; the front one is being written
  struct Pending {
    std::uint32_t request_id = 0;
    ReplyHandler on_reply;
  };
  std::deque<Pending> pending_;
  std::uint32_t last_request_id_ = 0;
  bool ready_ = false;
  bool closed_ = false;
  bool writing_ = false;
  bool untrusted_ = false;
  std::uint64_t bad_frames_ = 0;
};

}  // namespace ricochet::bot
